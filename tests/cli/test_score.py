"""``novelty score``: its output never replaces the model or the scans it reads."""

import numpy as np

from novelty.cli import main


def test_an_output_naming_the_model_or_the_data_is_refused_before_anything_is_read(tmp_path, capsys):
    data = tmp_path / "scans.csv"
    data.write_text("a,b\n0.1,0.2\n0.3,0.4\n")
    model = tmp_path / "m.npz"
    assert main(["run", "hsom", "--data", str(data), "--param", "n_rows=2", "--save", str(model)]) == 0
    saved = model.read_bytes()
    capsys.readouterr()
    for option, target in (("--model", model), ("--data", data)):
        assert main(["score", "--model", str(model), "--data", str(data), "--out", str(target)]) == 2
        captured = capsys.readouterr()
        assert f"--out {target} is the file {option} names" in captured.err and captured.out == ""
    assert model.read_bytes() == saved and data.read_text() == "a,b\n0.1,0.2\n0.3,0.4\n"
    assert np.load(model, allow_pickle=False).files   # still a model file
