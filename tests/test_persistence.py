"""Model files: exact round trips, the npz + JSON format, and every kind of bad file
refused with ModelFileError without running anything."""

import io
import json
import os
import pickle
import stat
import struct
import tempfile
import time
import tracemalloc
import zipfile
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import novelty
from novelty._component import StateError
from novelty.clusterers.som import SOM
from novelty.filter import HabituatingFilter
from novelty.persistence import FORMAT_VERSION, ModelFileError
from tests.damaged import damaging

from ._kernels.kernel_helpers import within_fixed_point
from .registered import missing_requirements


def fitted(**params):
    det = novelty.make("hsom", n_rows=3, n_columns=4, **params)
    det.fit(np.random.default_rng(0).uniform(size=(30, 5)))
    return det


@pytest.fixture
def saved(tmp_path):
    det = fitted()
    path = tmp_path / "model.npz"
    det.save(path)
    return det, path


def read_entries(path):
    with np.load(path, allow_pickle=False) as npz:
        return {name: npz[name] for name in npz.files}


def meta_of(entries):
    return json.loads(entries["meta"].tobytes().decode("utf-8"))


def with_meta(entries, meta):
    out = dict(entries)
    out["meta"] = np.frombuffer(json.dumps(meta).encode("utf-8"), dtype=np.uint8)
    return out


def write_entries(path, entries):
    with open(path, "wb") as fh:
        np.savez(fh, **entries)  # savez pickles object arrays: the attacker's tool
    return path


def all_state(det):
    out = {}
    for owner, obj in (("", det), ("clusterer_.", det.clusterer_), ("synapse_.", det.synapse_)):
        for name, value in vars(obj).items():
            # the compiled loop's engine is not state: built on first use (a loaded model builds
            # its own); nor are the counts of attributes set (Component.__setattr__), a part's marks
            # of the engine that holds it and writes it, nor the lock
            if name in ("clusterer_", "synapse_", "_engine", "_changes", "_parts_seen", "_lock", "_held",
                        "_writing", "_locked"):
                continue
            out[owner + name] = value
    return out


def assert_identical(a, b):
    sa, sb = all_state(a), all_state(b)
    assert sa.keys() == sb.keys()
    for key in sa:
        u, v = sa[key], sb[key]
        if isinstance(u, np.ndarray):
            assert u.dtype == v.dtype and u.shape == v.shape, key
            assert u.tobytes() == v.tobytes(), key  # bit for bit
        elif isinstance(u, list):
            assert len(u) == len(v) and all(np.array_equal(p, q) for p, q in zip(u, v)), key
        elif hasattr(u, "get_params"):
            assert type(u) is type(v) and repr(u.get_params()) == repr(v.get_params()), key
        else:
            assert type(u) is type(v) and u == v, key


# ------------------------------------------------------------ round trips
def test_round_trip_is_exact(saved):
    det, path = saved
    loaded = novelty.load(path)
    assert type(loaded) is HabituatingFilter
    assert repr(loaded.get_params(deep=True)) == repr(det.get_params(deep=True))
    assert_identical(det, loaded)
    Y = np.random.default_rng(1).uniform(size=(40, 5))
    assert det.novelty(Y).tobytes() == loaded.novelty(Y).tobytes()
    assert det.stream(Y).tobytes() == loaded.stream(Y).tobytes()
    assert [det.score_learn_one(y) for y in Y] == [loaded.score_learn_one(y) for y in Y]
    assert_identical(det, loaded)


def test_loaded_model_is_independent_of_the_original(saved):
    det, path = saved
    loaded = novelty.load(path)
    loaded.partial_fit(np.zeros((3, 5)))
    assert not np.array_equal(det.clusterer_.weights_, loaded.clusterer_.weights_)
    again = novelty.load(path)
    assert_identical(det, again)
    assert again.clusterer_.weights_.flags.writeable and again.synapse_.efficacy_.flags.writeable


@st.composite
def random_models(draw):
    method = draw(st.sampled_from(["euler", "exact"]))
    alpha = draw(st.floats(0.5, 2.0))
    low = alpha if method == "euler" else 0.1
    params = dict(
        n_rows=draw(st.integers(1, 4)),
        n_columns=draw(st.integers(1, 4)),
        learning_rate=draw(st.floats(0.0, 1.0)),
        radius=draw(st.sampled_from([0, 1, 2, 1.5])),
        decay=draw(st.sampled_from(["constant", "linear", "asymptotic"])),
        decay_steps=draw(st.integers(1, 30)),
        learning_rate_final=draw(st.floats(0.0, 1.0)),
        init=draw(st.sampled_from(["uniform", "sample"])),
        init_range=draw(st.sampled_from([(0.0, 1.0), (-2.5, 3.0)])),
        alpha=alpha,
        tau_winner=draw(st.floats(low, 20.0)),
        tau_neighbour=draw(st.floats(low, 20.0)),
        y0=(y0 := draw(st.floats(0.5, 1.0))),
        others=draw(st.sampled_from(["hold", "forget"])),
        method=method,
        threshold=draw(st.floats(-1.0, 1.0)),
        # at most Stanley's fixed point y0 - S/alpha = 0, as the filter computes it: S = alpha * y0
        # rounds above it for some (alpha, y0), and the filter refuses such a stimulus
        stimulus=within_fixed_point(draw(st.floats(0.0, 1.0)), alpha, y0),
        n_epochs=draw(st.integers(1, 2)),
        random_state=draw(st.integers(0, 2**31 - 1)),
    )
    if params["others"] == "forget" and draw(st.booleans()):
        params["tau_forget"] = draw(st.floats(low, 20.0))
    seed = draw(st.integers(0, 2**16))
    n_features = draw(st.integers(1, 4))
    timestamps = draw(st.booleans())
    return params, seed, n_features, timestamps


AT_THE_FIXED_POINT = dict(  # the strategy's largest stimulus where alpha * y0 rounds past the fixed point
    n_rows=2, n_columns=2, learning_rate=0.5, radius=1, decay="constant", decay_steps=3, learning_rate_final=0.1,
    init="uniform", init_range=(0.0, 1.0), alpha=1.72, tau_winner=20.0, tau_neighbour=20.0, y0=0.956,
    others="hold", method="euler", threshold=0.5, stimulus=within_fixed_point(1.0, 1.72, 0.956), n_epochs=2,
    random_state=0)


@settings(max_examples=25, deadline=None)
@given(random_models())
@example((AT_THE_FIXED_POINT, 0, 3, False))
def test_round_trip_on_random_models_is_exact(case):
    params, seed, n_features, timestamps = case
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(rng.integers(1, 25), n_features))
    Y = rng.normal(size=(15, n_features))
    det = novelty.make("hsom", **params)
    if timestamps:
        det.fit(X, timestamps=np.cumsum(rng.uniform(0, 3, len(X))))
    else:
        det.fit(X)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "m.npz"
        det.save(path)
        loaded = novelty.load(path)
    assert_identical(det, loaded)
    assert det.novelty(Y).tobytes() == loaded.novelty(Y).tobytes()
    assert det.predict(Y).tobytes() == loaded.predict(Y).tobytes()
    t_next = None if not timestamps else det.last_time_ + np.arange(1, 16, dtype=float)
    assert det.stream(Y, timestamps=t_next).tobytes() == loaded.stream(Y, timestamps=t_next).tobytes()
    assert_identical(det, loaded)


# ----------------------------------------------------------------- format
def test_file_is_a_zip_of_npy_with_json_meta_and_no_pickle(saved):
    det, path = saved
    with zipfile.ZipFile(path) as zf:
        names = zf.namelist()
        assert all(name.endswith(".npy") for name in names)
        assert "meta.npy" in names
        for name in names:
            with zf.open(name) as fh:
                major, _ = np.lib.format.read_magic(fh)
                read_header = np.lib.format.read_array_header_1_0 if major == 1 else np.lib.format.read_array_header_2_0
                _, _, dtype = read_header(fh)
                assert dtype != object and not dtype.hasobject, name
    entries = read_entries(path)  # loads with allow_pickle=False
    meta = meta_of(entries)
    assert meta["format"] == "novelty-model" and meta["format_version"] == FORMAT_VERSION == 1
    assert meta["novelty_version"] == novelty.__version__
    root = meta["root"]
    assert (root["kind"], root["name"]) == ("detector", "habituating")
    assert root["children"]["clusterer_"]["name"] == "som"
    assert root["children"]["synapse_"]["name"] == "stanley"
    assert root["params"]["clusterer"]["__component__"]["params"]["n_rows"] == 3
    np.testing.assert_array_equal(entries["root/clusterer_/weights_"], det.clusterer_.weights_)
    np.testing.assert_array_equal(entries["root/synapse_/efficacy_"], det.synapse_.efficacy_)


def test_save_leaves_no_temporary_file(tmp_path):
    fitted().save(tmp_path / "a.npz")
    assert os.listdir(tmp_path) == ["a.npz"]


def test_save_accepts_str_paths_and_overwrites(tmp_path):
    path = str(tmp_path / "m.npz")
    fitted().save(path)
    det = fitted(random_state=3)
    det.save(path)
    assert_identical(det, novelty.load(path))


def test_unfitted_model_cannot_be_saved(tmp_path):
    with pytest.raises(StateError, match="not fitted; there is nothing to save"):
        novelty.make("hsom").save(tmp_path / "m.npz")
    assert os.listdir(tmp_path) == []


class UnregisteredSOM(SOM):
    """A SOM subclass nobody registered."""


def test_unregistered_component_cannot_be_saved(tmp_path):
    det = HabituatingFilter(clusterer=UnregisteredSOM(n_rows=2, n_columns=2)).fit(np.zeros((2, 3)))
    with pytest.raises(StateError, match=r"UnregisteredSOM is not registered as a clusterer.*novelty.register_clusterer"):
        det.save(tmp_path / "m.npz")
    assert os.listdir(tmp_path) == []  # nothing half-written


def test_generator_seed_cannot_be_saved(tmp_path):
    det = novelty.make("hsom", n_rows=2, n_columns=2, random_state=np.random.default_rng(0))
    det.fit(np.zeros((2, 3)))
    with pytest.raises(StateError, match="an int seed for random_state"):
        det.save(tmp_path / "m.npz")


# ---------------------------------------------------------------- bad files
class Payload:
    """Unpickling this object creates a directory: proof that code ran."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (os.mkdir, (self.marker,))


def object_array(marker):
    arr = np.empty(2, dtype=object)
    arr[0], arr[1] = Payload(marker), 1.0
    return arr


def test_the_payload_works_when_unpickled(tmp_path):
    # positive control: the crafted entry below really would run code
    marker = tmp_path / "ran"
    path = write_entries(tmp_path / "evil.npz", {"x": object_array(marker)})
    with np.load(path, allow_pickle=True) as npz:
        npz["x"]
    assert marker.exists()


@pytest.mark.parametrize("entry", ["root/clusterer_/weights_", "root/synapse_/efficacy_", "meta"])
def test_object_array_is_refused_without_unpickling(saved, tmp_path, entry):
    _, path = saved
    marker = tmp_path / "ran"
    entries = read_entries(path)
    entries[entry] = object_array(marker)
    evil = write_entries(tmp_path / "evil.npz", entries)
    with pytest.raises(ModelFileError):
        novelty.load(evil)
    assert not marker.exists()


def test_a_plain_pickle_is_refused_without_unpickling(tmp_path):
    marker = tmp_path / "ran"
    path = tmp_path / "evil.npz"
    path.write_bytes(pickle.dumps(Payload(marker)))
    with pytest.raises(ModelFileError, match="not a novelty model file"):
        novelty.load(path)
    path2 = tmp_path / "evil.npy"
    np.save(path2, object_array(marker), allow_pickle=True)
    with pytest.raises(ModelFileError):
        novelty.load(path2)
    assert not marker.exists()


@pytest.mark.parametrize("fraction", [0.0, 0.05, 0.3, 0.5, 0.9, 0.999])
def test_truncated_file(saved, tmp_path, fraction):
    _, path = saved
    data = path.read_bytes()
    cut = tmp_path / "cut.npz"
    cut.write_bytes(data[: int(len(data) * fraction)])
    with pytest.raises(ModelFileError):
        novelty.load(cut)


@pytest.mark.parametrize("seed", range(5))
def test_random_bytes(tmp_path, seed):
    path = tmp_path / "noise.npz"
    path.write_bytes(np.random.default_rng(seed).bytes(2000))
    with pytest.raises(ModelFileError):
        novelty.load(path)


def test_zip_with_a_damaged_member(saved, tmp_path):
    _, path = saved
    data = bytearray(path.read_bytes())
    start = data.find(b"\x93NUMPY", 200)  # the second member's array header
    data[start + 60 : start + 90] = b"\xff" * 30
    bad = tmp_path / "bad.npz"
    bad.write_bytes(bytes(data))
    with pytest.raises(ModelFileError):
        novelty.load(bad)


def test_single_array_and_foreign_npz(tmp_path):
    np.save(tmp_path / "a.npy", np.zeros(3))
    with pytest.raises(ModelFileError, match="single numpy array"):
        novelty.load(tmp_path / "a.npy")
    write_entries(tmp_path / "b.npz", {"weights": np.zeros(3)})
    with pytest.raises(ModelFileError, match="no 'meta' entry"):
        novelty.load(tmp_path / "b.npz")


def test_missing_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        novelty.load(tmp_path / "absent.npz")


def test_newer_format_version(saved, tmp_path):
    _, path = saved
    entries = read_entries(path)
    meta = meta_of(entries)
    meta["format_version"] = FORMAT_VERSION + 1
    bad = write_entries(tmp_path / "new.npz", with_meta(entries, meta))
    with pytest.raises(ModelFileError, match=r"model format 2 .*reads format 1 or older\. Upgrade novelty"):
        novelty.load(bad)


def tamper_meta(saved, tmp_path, change):
    _, path = saved
    entries = read_entries(path)
    meta = meta_of(entries)
    change(meta)
    return write_entries(tmp_path / "tampered.npz", with_meta(entries, meta))


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda m: m["root"]["children"]["clusterer_"].update(name="no-such-net"), r"needs the clusterer 'no-such-net', which is not registered"),
        (lambda m: m["root"].update(name="os:system"), r"not registered"),
        (lambda m: m["root"]["children"]["synapse_"].update(kind="module"), r"invalid component"),
        (lambda m: m["root"]["params"]["clusterer"]["__component__"].update(name="nope"), r"not registered"),
        (lambda m: m["root"]["children"]["clusterer_"]["params"].update(evil=1), r"unknown parameters \['evil'\]"),
        (lambda m: m["root"]["children"]["clusterer_"]["params"].update(learning_rate=7.0), r"invalid parameters.*'learning_rate'"),
        (lambda m: m["root"]["children"]["clusterer_"]["params"].update(n_rows=4), r"units"),
        (lambda m: m["root"]["params"].update(threshold={"__import__": "os"}), r"Unexpected object"),
        (lambda m: m["root"]["children"]["clusterer_"]["arrays"].append("ghost_"), r"lacks the array"),
        (lambda m: m["root"]["values"].update(n_features_in_=7), r"n_features_in_"),
        (lambda m: m["root"]["values"].update(n_features_in_=5.0), r"n_features_in_ must be an int in \[1, 2\*\*53\]"),
        (lambda m: m["root"]["values"].update(last_time_="abc"), r"last_time_ must be None or a finite number"),
        (lambda m: m["root"]["values"].update(last_time_=[1, 2]), r"last_time_ must be None or a finite number"),
        (lambda m: m["root"]["children"]["clusterer_"]["values"].update(n_updates_=1.5), r"n_updates_ must be an int"),
        (lambda m: m["root"]["children"]["clusterer_"]["values"].update(next_unit_id_=3), r"unique and below next_unit_id_"),
        (lambda m: m["root"]["values"].update(__class__=1), r"not a learned-state attribute"),
        (lambda m: m.update(format="other"), r"not a novelty model file"),
        (lambda m: m.update(format_version="1"), r"invalid format version"),
        (lambda m: m.update(root=[]), r"malformed"),
        (lambda m: m["root"]["children"].update(synapse_=None), r"malformed"),
    ],
)
def test_tampered_metadata(saved, tmp_path, change, message):
    bad = tamper_meta(saved, tmp_path, change)
    with pytest.raises(ModelFileError, match=message):
        novelty.load(bad)


def test_meta_that_is_not_json(saved, tmp_path):
    _, path = saved
    entries = read_entries(path)
    entries["meta"] = np.frombuffer(b"{not json", dtype=np.uint8)
    with pytest.raises(ModelFileError):
        novelty.load(write_entries(tmp_path / "a.npz", entries))
    entries["meta"] = np.zeros(3)
    with pytest.raises(ModelFileError, match="not JSON text"):
        novelty.load(write_entries(tmp_path / "b.npz", entries))


@pytest.mark.parametrize(
    "entry, replace",
    [
        ("root/clusterer_/weights_", lambda w: w[:-1]),  # one unit too few
        ("root/clusterer_/weights_", lambda w: np.vstack([w, w[:1]])),
        ("root/clusterer_/weights_", lambda w: w[:, :-1]),  # wrong n_features
        ("root/clusterer_/weights_", lambda w: w.ravel()),
        ("root/clusterer_/weights_", lambda w: np.where(w > 0.5, np.nan, w)),
        ("root/clusterer_/weights_", lambda w: w.astype(np.complex128)),
        ("root/clusterer_/unit_ids_", lambda u: u.astype(np.float64)),
        ("root/clusterer_/unit_ids_", lambda u: np.zeros_like(u)),  # not unique
        ("root/synapse_/efficacy_", lambda e: e[:-1]),  # fewer synapses than units
        ("root/synapse_/efficacy_", lambda e: np.full_like(e, np.inf)),
        ("root/synapse_/efficacy_", lambda e: e.reshape(1, -1)),
    ],
)
def test_tampered_arrays(saved, tmp_path, entry, replace):
    _, path = saved
    entries = read_entries(path)
    entries[entry] = replace(entries[entry])
    with pytest.raises(ModelFileError):
        novelty.load(write_entries(tmp_path / "bad.npz", entries))


def test_fewer_units_than_the_map_has(saved, tmp_path):
    _, path = saved
    entries = read_entries(path)  # weights and ids consistent with each other, not with 3 x 4
    entries["root/clusterer_/weights_"] = entries["root/clusterer_/weights_"][:-1]
    entries["root/clusterer_/unit_ids_"] = entries["root/clusterer_/unit_ids_"][:-1]
    with pytest.raises(ModelFileError, match=r"SOM.weights_ has 11 units; a 3 x 4 map has 12"):
        novelty.load(write_entries(tmp_path / "bad.npz", entries))


def test_saved_timestamps_round_trip(tmp_path):
    det = fitted()
    det.partial_fit(np.zeros((2, 5)), timestamps=[100.0, 101.5])
    det.save(tmp_path / "m.npz")
    loaded = novelty.load(tmp_path / "m.npz")
    assert loaded.last_time_ == 101.5
    with pytest.raises(ValueError, match="must not decrease"):
        loaded.learn_one(np.zeros(5), t=100.0)


def test_missing_array_entry(saved, tmp_path):
    _, path = saved
    entries = read_entries(path)
    del entries["root/synapse_/efficacy_"]
    with pytest.raises(ModelFileError, match=r"lacks the array 'root/synapse_/efficacy_'"):
        novelty.load(write_entries(tmp_path / "bad.npz", entries))


def test_a_text_file_is_not_called_pickled_data(tmp_path):
    """numpy would call any non-npy, non-zip file 'pickled data' and suggest allow_pickle."""
    path = tmp_path / "notes.npz"
    path.write_text("hello\n")
    with pytest.raises(ModelFileError, match="not an .npz archive") as info:
        novelty.load(path)
    assert "pickle" not in str(info.value)


@pytest.mark.parametrize("keys", [["sonar_3", "sonar_1", "bumper", "sonar_2", "odometry"], [4, 0, 3, 1, 2]])
def test_feature_names_of_dict_scans_round_trip(tmp_path, keys):
    det = novelty.make("hsom", n_rows=3, n_columns=4)
    rng = np.random.default_rng(0)
    for x in rng.uniform(size=(30, 5)):
        det.learn_one(dict(zip(keys, x.tolist())))
    det.save(tmp_path / "m.npz")
    loaded = novelty.load(tmp_path / "m.npz")
    assert loaded.feature_names_in_.dtype == det.feature_names_in_.dtype
    assert loaded.feature_names_in_.tolist() == sorted(keys)
    x = dict(zip(keys[::-1], rng.uniform(size=5).tolist()))
    assert loaded.score_one(x) == det.score_one(x)
    with pytest.raises(ValueError, match="yet now missing"):
        loaded.score_one({k: 0.5 for k in keys[1:]})


@pytest.mark.parametrize("names, message", [
    (np.array(["a", "a", "b", "c", "d"], dtype=object), "5 distinct names"),
    (np.array(["a", "b"], dtype=object), "5 distinct names"),
    (np.array([0.5, 1, 2, 3, 4]), "all strings or all integers"),
])
def test_bad_feature_names_in_a_file_are_refused(tmp_path, names, message):
    det = fitted()
    if names.dtype == object:
        det.feature_names_in_ = names
        with pytest.raises(StateError, match=message):  # save refuses what load would refuse
            det.save(tmp_path / "m.npz")
        det.feature_names_in_ = np.array(list("abcde"), dtype=object)
        det.save(tmp_path / "m.npz")
        entries = read_entries(tmp_path / "m.npz")
        meta = meta_of(entries)
        meta["root"]["values"]["feature_names_in_"] = {"__strings__": names.tolist()}
        write_entries(tmp_path / "m.npz", with_meta(entries, meta))
    else:  # a float array is written as an array; tamper with the file instead
        det.feature_names_in_ = np.arange(5)
        det.save(tmp_path / "m.npz")
        entries = read_entries(tmp_path / "m.npz")
        entries["root/feature_names_in_"] = names
        write_entries(tmp_path / "m.npz", entries)
    with pytest.raises(ModelFileError, match=message):
        novelty.load(tmp_path / "m.npz")


@pytest.mark.parametrize("n_scans", [1, 12, 40])  # no scale yet, calibrating, calibrated
@pytest.mark.parametrize("name,params", [
    ("hsom", {"novelty_rule": "mismatch", "calibration_scans": 20}),
    ("gwr-novelty", {"novelty_rule": "mismatch", "activity_threshold": "auto",
                     "firing_condition": False, "new_unit_wins": True, "calibration_scans": 20}),
    ("hsom", {"novelty_rule": "mismatch", "match_scale": "scott", "calibration_scans": 20}),
    ("kmeans-stanley", {"calibration_scans": 20, "n_clusters": 25}),  # units still being placed at 12
    ("gwr-explore", {"calibration_scans": 20}),
])
def test_match_scale_and_calibration_round_trip(tmp_path, name, params, n_scans):
    rng = np.random.default_rng(0)
    det = novelty.make(name, **params).fit(rng.uniform(size=(n_scans, 5)))
    det.save(tmp_path / "m.npz")
    loaded = novelty.load(tmp_path / "m.npz")
    assert_identical(det, loaded)
    assert loaded.match_scale_ == det.match_scale_
    Y = rng.uniform(size=(30, 5))
    assert det.novelty(Y).tobytes() == loaded.novelty(Y).tobytes()
    assert det.stream(Y).tobytes() == loaded.stream(Y).tobytes()  # calibration goes on alike
    assert loaded.match_scale_ == det.match_scale_ is not None
    def flat(model):  # the rule and the GWR's radius among them (the components compare by identity)
        return {k: v for k, v in model.get_params().items() if k not in ("clusterer", "synapse")}

    assert flat(loaded) == flat(det)


def test_contamination_threshold_and_labels_round_trip(tmp_path):
    det = fitted(contamination=0.2)
    det.save(tmp_path / "m.npz")
    loaded = novelty.load(tmp_path / "m.npz")
    assert loaded.decision_scores_.tobytes() == det.decision_scores_.tobytes()
    assert loaded.threshold_ == det.threshold_ != det.threshold
    np.testing.assert_array_equal(loaded.labels_, det.labels_)


# ------------------------------------------------- reading is bounded in memory
def peak_mib(fn):
    """Peak memory traced while ``fn`` runs (numpy's buffers included), in MiB."""
    tracemalloc.start()
    try:
        fn()
        return tracemalloc.get_traced_memory()[1] / 2**20
    finally:
        tracemalloc.stop()


def npy_header(shape, dtype="<f8") -> bytes:
    buffer = io.BytesIO()
    np.lib.format.write_array_header_1_0(buffer, {"descr": dtype, "fortran_order": False, "shape": shape})
    return buffer.getvalue()


def rewrite_member(path, out, name, write):
    """``path`` copied to ``out`` with the member ``name`` written by ``write(zip, name)``."""
    with zipfile.ZipFile(path) as src, zipfile.ZipFile(out, "w") as dst:
        for info in src.infolist():
            if info.filename == name:
                write(dst, name)
            else:
                dst.writestr(info, src.read(info))
    return out


def test_a_zip_bomb_is_refused_before_it_is_inflated(saved, tmp_path):
    _, path = saved
    shape = (2**21, 5)  # 80 MiB of zeros in a file of about 80 kB

    def bomb_writer(zf, name):
        info = zipfile.ZipInfo(name)
        info.compress_type = zipfile.ZIP_DEFLATED
        with zf.open(info, "w", force_zip64=True) as fh:
            fh.write(npy_header(shape))
            zeros = bytes(2**20)
            for _ in range(shape[0] * shape[1] * 8 // len(zeros)):
                fh.write(zeros)

    bad = rewrite_member(path, tmp_path / "bomb.npz", "root/clusterer_/weights_.npy", bomb_writer)
    assert bad.stat().st_size < 200_000

    def load():
        with pytest.raises(ModelFileError, match="compressed"):
            novelty.load(bad)

    assert peak_mib(load) < 8


@pytest.mark.parametrize("shape", [(10**12, 16), (2**62, 2**62), (12, 10**6)])
def test_a_declared_shape_larger_than_the_data_is_refused_before_allocation(saved, tmp_path, shape):
    _, path = saved
    bad = rewrite_member(path, tmp_path / "big.npz", "root/clusterer_/weights_.npy",
                         lambda zf, name: zf.writestr(name, npy_header(shape) + bytes(480)))

    def load():
        with pytest.raises(ModelFileError, match=r"declares shape .* but holds 480 bytes"):
            novelty.load(bad)

    assert peak_mib(load) < 8


@pytest.mark.parametrize("depth", [10_000, 200_000])
def test_deeply_nested_metadata_is_a_model_file_error(saved, tmp_path, depth):
    _, path = saved
    entries = read_entries(path)
    entries["meta"] = np.frombuffer(b"[" * depth + b"]" * depth, dtype=np.uint8)
    with pytest.raises(ModelFileError):
        novelty.load(write_entries(tmp_path / "deep.npz", entries))


def central_record(data: bytes, name: str) -> int:
    """Offset of the central-directory record of member ``name``."""
    return data.rindex(b"PK\x01\x02", 0, data.rindex(name.encode()))


@pytest.mark.parametrize("offset, flip", [(8, 0x01), (6, 0x40), (10, 0x0C)],
                         ids=["encrypted-flag", "version-needed", "compression-method"])
def test_damaged_zip_directory_is_a_model_file_error(saved, tmp_path, offset, flip):
    _, path = saved
    data = bytearray(path.read_bytes())
    data[central_record(data, "root/clusterer_/unit_ids_.npy") + offset] ^= flip
    bad = tmp_path / "flipped.npz"
    bad.write_bytes(bytes(data))
    with pytest.raises(ModelFileError):
        novelty.load(bad)


@pytest.mark.parametrize("header", [b"{'descr': '<f8', 'fortran_order': False, 'shape': (12, 5\x00), }",
                                    b"{'descr': '<f8', 'fortran_order': False, 'shape': (12, 5), ",
                                    b"{'descr': '<f8', 'fortran_order': False, 'shape': (12 + 5), }",
                                    b"{'descr': 'O', 'fortran_order': False, 'shape': (12, 5), }"])
def test_damaged_array_header_is_a_model_file_error(saved, tmp_path, header):
    _, path = saved
    with zipfile.ZipFile(path) as zf:
        data = zf.read("root/clusterer_/weights_.npy")
    start = data.index(b"{")
    old = data[start : data.index(b"}") + 1]
    new = data[:start] + header.ljust(len(old)) + data[start + len(old):]
    bad = rewrite_member(path, tmp_path / "header.npz", "root/clusterer_/weights_.npy",
                         lambda zf, name: zf.writestr(name, new))  # the archive is sound, the header not
    with pytest.raises(ModelFileError):
        novelty.load(bad)


# ---------------------------------------------------------- impossible state
def tamper_array(saved, tmp_path, entry, value):
    _, path = saved
    entries = read_entries(path)
    entries[entry] = value(entries[entry])
    return write_entries(tmp_path / "tampered.npz", entries)


@pytest.mark.parametrize(
    "entry, value, message",
    [
        ("root/synapse_/efficacy_", lambda e: np.where(np.arange(e.size) == 3, 5.0, e),
         r"StanleySynapse.efficacy_ must lie in \[0.0476.*, 1\]"),
        ("root/synapse_/efficacy_", lambda e: np.where(np.arange(e.size) == 0, -1e300, e),
         r"efficacy_ must lie in"),
        ("root/clusterer_/weights_", lambda w: w.astype(np.float16), r"weights_ must be a float64 array; got float16"),
        ("root/synapse_/efficacy_", lambda e: e.astype(np.float32), r"efficacy_ must be a float64 array; got float32"),
        ("root/clusterer_/unit_ids_", lambda u: u.astype(np.uint64) + np.uint64(2**63),
         r"unit_ids_ must hold integers within int64"),
    ],
)
def test_impossible_arrays_are_refused(saved, tmp_path, entry, value, message):
    with pytest.raises(ModelFileError, match=message):
        novelty.load(tamper_array(saved, tmp_path, entry, value))


@pytest.mark.parametrize("field, value", [("n_updates_", 2**64), ("n_updates_", 2**53 + 1),
                                          ("next_unit_id_", 2**63)])
def test_counters_beyond_any_run_are_refused(saved, tmp_path, field, value):
    bad = tamper_meta(saved, tmp_path, lambda m: m["root"]["children"]["clusterer_"]["values"].update(
        {field: value}))
    with pytest.raises(ModelFileError, match=rf"{field} must be an int in \[\d+, 2\*\*53\]"):
        novelty.load(bad)


def test_a_parameter_beyond_int64_is_refused_at_load(saved, tmp_path):
    """A count no run reaches (2**70 clusters) is a model file's error at load, not a ValueError
    when the compiled steps first read the parameters."""
    bad = tamper_meta(saved, tmp_path, lambda m: m["root"]["children"]["clusterer_"]["params"].update(
        {next(iter(m["root"]["children"]["clusterer_"]["params"])): 2**70}))
    with pytest.raises(ModelFileError, match=r"= 1180591620717411303424, beyond the 64-bit integers"):
        novelty.load(bad)


def test_efficacy_range_follows_the_stimulus(tmp_path):
    """Under a stimulus S, Stanley's efficacy stays in [y0 - S/alpha, y0]: S = alpha y0 reaches 0."""
    det = fitted(stimulus=1.05)
    det.partial_fit(np.tile(det.clusterer_.weights_[:1], (40, 1)))
    assert det.synapse_.efficacy_.min() < 1 - 1 / 1.05  # below the range of S = 1
    det.save(tmp_path / "m.npz")
    assert_identical(det, novelty.load(tmp_path / "m.npz"))


def test_efficacies_the_model_reaches_below_its_fixed_point_load(tmp_path):
    """S = alpha y0 with y0 - S/alpha exactly 0: the efficacy reaches a rounding below 0, and still loads."""
    alpha, y0 = 1.05, 0.91
    assert y0 - (alpha * y0) / alpha == 0.0  # the fixed point as the filter computes it
    det = novelty.make("hsom", n_rows=1, n_columns=1, alpha=alpha, y0=y0, stimulus=alpha * y0,
                       tau_winner=3.33)
    scan = np.full(3, 0.5)
    det.partial_fit(np.tile(scan, (120, 1)))
    assert det.synapse_.efficacy_[0] == pytest.approx(-8.4e-18, rel=0.01)  # outside the range [0, y0]
    det.save(tmp_path / "m.npz")
    loaded = novelty.load(tmp_path / "m.npz")
    assert_identical(det, loaded)
    assert det.novelty(scan[None]).tobytes() == loaded.novelty(scan[None]).tobytes()


@settings(max_examples=60, deadline=None)
@given(alpha=st.floats(0.5, 3.3), y0=st.floats(0.05, 1.0))  # alpha <= tau_winner (Euler)
@example(alpha=1.72, y0=0.956)  # alpha * y0 rounds past the fixed point: y0 - S/alpha = -1.1e-16
def test_a_stimulus_written_as_alpha_y0_is_accepted_and_one_past_it_refused(alpha, y0):
    """S = alpha * y0 as Python computes it is accepted whichever side of Stanley's fixed point
    the product rounds to; a stimulus past it by more than roundings is refused."""
    novelty.make("hsom", n_rows=1, n_columns=2, alpha=alpha, y0=y0,
                 stimulus=alpha * y0).fit(np.zeros((2, 3)))
    with pytest.raises(ValueError, match=r"efficacy is the novelty, on \[0, 1\]"):
        novelty.make("hsom", alpha=alpha, y0=y0, stimulus=alpha * y0 * (1 + 1e-12)).fit(np.zeros((2, 3)))


def test_gwr_firing_counters_are_checked(tmp_path):
    det = novelty.make("gwr-novelty").fit(np.random.default_rng(0).uniform(size=(30, 3)))
    det.save(tmp_path / "m.npz")
    entries = read_entries(tmp_path / "m.npz")
    entries["root/clusterer_/firing_/efficacy_"] = entries["root/clusterer_/firing_/efficacy_"] + 2.0
    with pytest.raises(ModelFileError, match=r"efficacy_ must lie in"):
        novelty.load(write_entries(tmp_path / "bad.npz", entries))


# --------------------------------------------------- saving what loads, only
def test_a_state_that_would_not_load_is_not_saved(tmp_path):
    path = tmp_path / "m.npz"
    good = fitted()
    good.save(path)
    before = path.read_bytes()
    bad = fitted()
    with damaging(bad):
        bad.clusterer_.weights_[0, 0] = np.nan
    with pytest.raises(StateError, match=r"Not saved to .*m.npz.*NaN"):
        bad.save(path)
    assert path.read_bytes() == before and os.listdir(tmp_path) == ["m.npz"]
    with damaging(bad):
        bad.clusterer_.weights_[0, 0] = 0.5
        bad.synapse_.efficacy_[1] = 7.0
    with pytest.raises(StateError, match=r"efficacy_ must lie in"):
        bad.save(path)
    assert path.read_bytes() == before and os.listdir(tmp_path) == ["m.npz"]


def test_saved_files_get_the_usual_mode(tmp_path):
    old = os.umask(0o022)
    try:
        fitted().save(tmp_path / "m.npz")
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "m.npz").stat().st_mode) == 0o644


# --------------------------------------------------------------------- fuzz
#: cheap settings for the detectors that are slow to fit; the others keep their defaults
_FAST = {"autoencoder-filter": {"max_iter": 20}, "gmm": {"n_components": 2},
         "isolation-forest": {"n_estimators": 10}}
CORRUPTIONS = ("bit flips", "header bit flips", "truncation", "random bytes", "member swap",
               "json edit", "array edit", "huge count")
#: counts a small file may declare: trees, units, iterations, components
HUGE_COUNTS = [10**6, 10**9, 2**31 - 1, 2**53, 2**63 - 1, 2**70]


def header_offsets(data: bytes) -> list[int]:
    """Offsets of the zip records and npy headers, where a flipped bit changes how a file is read."""
    offsets = []
    for magic, length in ((b"PK\x03\x04", 30), (b"PK\x01\x02", 46), (b"PK\x05\x06", 22),
                          (b"\x93NUMPY", 128)):
        start = data.find(magic)
        while start >= 0:
            offsets.extend(range(start, min(start + length, len(data))))
            start = data.find(magic, start + 1)
    return offsets


def rows_for(name: str, seed: int, n: int) -> np.ndarray:
    """Rows detector ``name`` reads: uniform in [0, 1]^3, or its own example rows where it reads a layout
    of its own (``input_layout``: the points input of habituating-map)."""
    det = novelty.make(name)
    if getattr(det, "input_layout", None) is not None:
        return type(det)._example_rows(seed, n)
    return np.random.default_rng(seed).uniform(size=(n, 3))


@pytest.fixture(scope="module")
def every_saved_model(tmp_path_factory):
    """One saved model of every registered detector installed: {name: file bytes}.

    A detector whose optional dependency is missing (``pyod`` without PyOD)
    cannot be fitted, so its file is left out.
    """
    from novelty.registry import detectors
    folder = tmp_path_factory.mktemp("models")
    files = {}
    for name in sorted(n for n in detectors if not missing_requirements(n)):
        path = folder / f"{name}.npz"
        novelty.make(name, **_FAST.get(name, {})).fit(rows_for(name, 0, 40)).save(path)
        files[name] = path.read_bytes()
    return files


def json_values():
    scalars = (st.none() | st.booleans() | st.integers(-2**70, 2**70) | st.text(max_size=8)
               | st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from([0, -1, 2**63, 1e308]))
    return st.recursive(scalars, lambda inner: st.lists(inner, max_size=3)
                        | st.dictionaries(st.text(max_size=6), inner, max_size=3), max_leaves=6)


def json_paths(node, path=()):
    yield path
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for key, child in items:
        yield from json_paths(child, path + (key,))


def _is_count(meta, path) -> bool:
    node = meta
    for key in path:
        node = node[key]
    return isinstance(node, int) and not isinstance(node, bool) and "format_version" not in path


def edit_json(meta, path, value, delete):
    if not path:
        return value
    parent = meta
    for key in path[:-1]:
        parent = parent[key]
    if delete and isinstance(parent, dict):
        del parent[path[-1]]
    else:
        parent[path[-1]] = value
    return meta


def random_array(draw):
    dtype = draw(st.sampled_from(["<f8", ">f8", "<f4", "<f2", "<i8", "<i4", "<u8", "|u1", "|b1"]))
    shape = tuple(draw(st.lists(st.integers(0, 6), max_size=3)))
    raw = draw(st.binary(min_size=int(np.prod(shape)) * np.dtype(dtype).itemsize,
                         max_size=int(np.prod(shape)) * np.dtype(dtype).itemsize))
    return np.frombuffer(raw, dtype=dtype).reshape(shape)


def rebuild(data: bytes, change) -> bytes:
    """The archive ``data`` with its members' contents changed by ``change(dict of name: bytes)``."""
    with zipfile.ZipFile(io.BytesIO(data)) as zf:
        members = {info.filename: zf.read(info) for info in zf.infolist()}
    change(members)
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w") as zf:
        for name, content in members.items():
            zf.writestr(name, content)
    return out.getvalue()


def npy_bytes(array) -> bytes:
    buffer = io.BytesIO()
    np.lib.format.write_array(buffer, array, allow_pickle=False)
    return buffer.getvalue()


@st.composite
def corruptions(draw, files):
    name = draw(st.sampled_from(sorted(files)))
    data = files[name]
    kind = draw(st.sampled_from(CORRUPTIONS))
    if kind == "bit flips":
        out = bytearray(data)
        for i in draw(st.lists(st.integers(0, len(data) * 8 - 1), min_size=1, max_size=8)):
            out[i // 8] ^= 1 << (i % 8)
        return name, kind, bytes(out)
    if kind == "header bit flips":
        out = bytearray(data)
        for i in draw(st.lists(st.sampled_from(header_offsets(data)), min_size=1, max_size=3)):
            out[i] ^= 1 << draw(st.integers(0, 7))
        return name, kind, bytes(out)
    if kind == "truncation":
        return name, kind, data[: draw(st.integers(0, len(data) - 1))]
    if kind == "random bytes":
        start = draw(st.integers(0, len(data) - 1))
        junk = draw(st.binary(min_size=1, max_size=64))
        return name, kind, data[:start] + junk + data[start + len(junk):]
    with zipfile.ZipFile(io.BytesIO(data)) as zf:
        names = zf.namelist()
    if kind == "member swap":
        a, b = draw(st.lists(st.sampled_from(names), min_size=2, max_size=2, unique=True))

        def swap(members):
            members[a], members[b] = members[b], members[a]
        return name, kind, rebuild(data, swap)
    if kind == "array edit":
        target = draw(st.sampled_from([n for n in names if n != "meta.npy"]))
        array = random_array(draw)
        return name, kind, rebuild(data, lambda members: members.update({target: npy_bytes(array)}))
    with zipfile.ZipFile(io.BytesIO(data)) as zf, zf.open("meta.npy") as fh:
        meta = json.loads(np.lib.format.read_array(fh).tobytes())
    if kind == "huge count":  # an integer of the metadata (a parameter, a counter) made huge
        counts = [p for p in json_paths(meta) if p and _is_count(meta, p)]
        meta = edit_json(meta, draw(st.sampled_from(counts)), draw(st.sampled_from(HUGE_COUNTS)), False)
        text = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
        return name, kind, rebuild(data, lambda members: members.update({"meta.npy": npy_bytes(text)}))
    path = draw(st.sampled_from(list(json_paths(meta))))
    depth = draw(st.sampled_from([0, 0, 0, 50, 5_000, 100_000]))  # a value nested this deep
    value = "<deep>" if depth else draw(json_values())
    meta = edit_json(meta, path, value, draw(st.booleans()))
    text = json.dumps(meta).replace('"<deep>"', "[" * depth + "]" * depth)
    text = np.frombuffer(text.encode(), dtype=np.uint8)
    return name, kind, rebuild(data, lambda members: members.update({"meta.npy": npy_bytes(text)}))


def test_corrupted_model_files_give_only_model_file_error(every_saved_model, tmp_path):
    """Random damage to a saved model of every registered detector: ModelFileError, or a model
    that works (scores finite novelty on new data and saves again)."""
    counts: dict = {}
    X = {name: rows_for(name, 1, 20) for name in every_saved_model}

    @settings(max_examples=400, deadline=None, suppress_health_check=list(HealthCheck))
    @given(corruptions(every_saved_model))
    def damaged(case):
        name, kind, data = case
        path = tmp_path / "damaged.npz"
        path.write_bytes(data)
        try:
            model = novelty.load(path)
        except ModelFileError:
            outcome = "refused"
        else:
            outcome = "loaded"
            assert np.all(np.isfinite(model.novelty(X[name]))), (name, kind)
            model.save(tmp_path / "again.npz")
        counts[kind, outcome] = counts.get((kind, outcome), 0) + 1

    start = time.perf_counter()
    damaged()
    elapsed = time.perf_counter() - start
    print(f"\nmodel-file fuzz: {sum(counts.values())} files in {elapsed:.1f} s: "
          + ", ".join(f"{k} {o} {n}" for (k, o), n in sorted(counts.items())))
    assert {kind for kind, _ in counts} == set(CORRUPTIONS)


def overlapping_archive(meta: bytes, names: list[str], kernel_bytes: int) -> bytes:
    """A stored zip whose array entries nest: each entry's bytes hold the next entry whole.

    The file holds the kernel once, but reading every entry reads it ``len(names)`` times
    (the overlapping-entries bomb).
    """
    def npy(payload: bytes) -> bytes:
        return npy_header((len(payload),), "|u1") + payload

    def local(name: str, body: bytes) -> bytes:
        return struct.pack("<4s2B4HL2L2H", b"PK\x03\x04", 20, 0, 0, 0, 0, 0x21, zlib.crc32(body),
                           len(body), len(body), len(name), 0) + name.encode()

    bodies = [npy(bytes(kernel_bytes))]
    for name in reversed(names[1:]):
        bodies.insert(0, npy(local(name, bodies[0]) + bodies[0]))
    entries, offset = [], 0
    for i, (name, body) in enumerate(zip(names, bodies)):
        entries.append((name, body, offset))
        if i + 1 < len(names):  # the next entry starts right after this one's npy header
            inner = local(names[i + 1], bodies[i + 1]) + bodies[i + 1]
            offset += len(local(name, body)) + len(body) - len(inner)
    meta_npy = npy(meta)
    data = local(names[0], bodies[0]) + bodies[0]
    entries.append(("meta.npy", meta_npy, len(data)))
    data += local("meta.npy", meta_npy) + meta_npy
    directory = b"".join(
        struct.pack("<4s4B4HL2L5H2L", b"PK\x01\x02", 20, 0, 20, 0, 0, 0, 0, 0x21, zlib.crc32(body),
                    len(body), len(body), len(name), 0, 0, 0, 0, 0, where) + name.encode()
        for name, body, where in entries)
    end = struct.pack("<4s4H2LH", b"PK\x05\x06", 0, 0, len(entries), len(entries), len(directory),
                      len(data), 0)
    return data + directory + end


def test_overlapping_entries_are_read_no_more_than_the_file_holds(saved, tmp_path):
    _, path = saved
    meta = meta_of(read_entries(path))
    attrs = [f"a{i}_" for i in range(40)]
    meta["root"]["arrays"] = attrs + meta["root"]["arrays"]  # read first
    names = [f"root/{a}.npy" for a in attrs]
    bad = tmp_path / "overlap.npz"
    bad.write_bytes(overlapping_archive(json.dumps(meta).encode(), names, 2**21))  # 2 MiB, 40 times
    with zipfile.ZipFile(bad) as zf:  # a sound archive, as far as zipfile can tell
        assert zf.getinfo(names[0]).file_size > 2**21

    def load():
        # the project's own check, or zipfile's where the Python has it (3.12, and 3.11 builds with the backport)
        with pytest.raises(ModelFileError, match="entries overlap|Overlapped entries"):
            novelty.load(bad)

    assert peak_mib(load) < 12


# ------------------------------------------------------- targets that are not regular files
def _fifo(path):
    os.mkfifo(path)
    return "FIFO"


def _symlink(path):
    (path.parent / "real.npz").write_bytes(b"kept")
    path.symlink_to(path.parent / "real.npz")
    return "symbolic link"


def _dangling_symlink(path):
    path.symlink_to(path.parent / "nowhere" / "x.npz")
    return "symbolic link"


def _directory(path):
    path.mkdir()
    return "directory"


def _device(path):
    try:
        os.mknod(path, 0o600 | stat.S_IFCHR, os.makedev(1, 3))  # the numbers of a null device
    except PermissionError:
        pytest.skip("making a device node needs privileges")
    return "character device"


@pytest.mark.parametrize("make_target", [_fifo, _symlink, _dangling_symlink, _directory, _device])
def test_save_refuses_a_target_that_is_not_a_regular_file(saved, tmp_path, make_target):
    det, _ = saved
    target = tmp_path / "target.npz"
    kind = make_target(target)
    before = os.lstat(target)
    with pytest.raises(FileExistsError, match=f"{kind}.*only a regular file is replaced"):
        det.save(target)
    after = os.lstat(target)
    assert (after.st_mode, after.st_ino) == (before.st_mode, before.st_ino)  # the same entry, untouched
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary file left
    if make_target is _symlink:
        assert (tmp_path / "real.npz").read_bytes() == b"kept"  # nothing written through the link


def test_save_refuses_a_target_that_appears_while_it_writes(saved, tmp_path, monkeypatch):
    # the check is made again just before the rename
    det, _ = saved
    target = tmp_path / "late.npz"
    real_savez = np.savez

    def savez_then_plant(fh, **arrays):
        real_savez(fh, **arrays)
        os.mkfifo(target)

    monkeypatch.setattr(np, "savez", savez_then_plant)
    with pytest.raises(FileExistsError, match="FIFO"):
        det.save(target)
    assert stat.S_ISFIFO(os.lstat(target).st_mode)


# ------------------------------------------------- state that learning cannot produce
def test_decision_scores_outside_the_novelty_range_are_refused(tmp_path):
    det = fitted(contamination=0.1)
    det.save(tmp_path / "m.npz")
    entries = read_entries(tmp_path / "m.npz")
    entries["root/decision_scores_"] = np.full_like(entries["root/decision_scores_"], 1e200)
    with pytest.raises(ModelFileError, match=r"decision_scores_ must lie in \[0.047619, 1\].*threshold_"):
        novelty.load(write_entries(tmp_path / "bad.npz", entries))


def test_weights_beyond_the_norm_bound_are_refused_and_at_the_bound_learning_goes_on(tmp_path):
    det = novelty.make("gng-stanley").fit(np.random.default_rng(0).uniform(size=(30, 4)))
    det.save(tmp_path / "m.npz")
    entries = read_entries(tmp_path / "m.npz")
    weights = entries["root/clusterer_/weights_"].copy()
    weights[0] = 1e200
    entries["root/clusterer_/weights_"] = weights
    with pytest.raises(ModelFileError, match=r"weights_ reach a norm of 2e\+200, beyond the bound 1e\+100"):
        novelty.load(write_entries(tmp_path / "far.npz", entries))
    weights[0] = 0.49e100  # a norm of 0.98e100: scans can be there, so the units can
    entries["root/clusterer_/weights_"] = weights
    loaded = novelty.load(write_entries(tmp_path / "edge.npz", entries))
    loaded.learn_one(np.full(4, -0.49e100))
    assert np.all(np.isfinite(loaded.clusterer_.errors_))
    loaded.save(tmp_path / "again.npz")


def test_a_baselines_training_scores_must_be_those_of_its_refit(tmp_path):
    det = novelty.make("isolation-forest", n_estimators=10, contamination=0.1)
    det.fit(np.random.default_rng(0).uniform(size=(40, 3)))
    det.save(tmp_path / "m.npz")
    assert novelty.load(tmp_path / "m.npz").threshold_ == det.threshold_
    entries = read_entries(tmp_path / "m.npz")
    entries["root/decision_scores_"] = entries["root/decision_scores_"][::-1] * 0.5  # within [0, 1]
    with pytest.raises(ModelFileError, match="not the novelty of samples_ under the refitted estimator"):
        novelty.load(write_entries(tmp_path / "bad.npz", entries))


def test_initial_weights_beyond_the_norm_bound_are_refused():
    det = novelty.make("hsom", n_rows=2, init="uniform", init_range=(0.0, 1e99))
    with pytest.raises(ValueError, match=r"initial weights reach a norm of .*beyond 1e\+100"):
        det.fit(np.zeros((3, 400)))
    assert not hasattr(det, "clusterer_")


def test_loading_a_fifo_is_refused_without_blocking(tmp_path):
    os.mkfifo(tmp_path / "m.npz")  # no writer: opening it would block forever
    with pytest.raises(ModelFileError, match="is a FIFO .*not a regular file"):
        novelty.load(tmp_path / "m.npz")


@pytest.mark.parametrize("value", [[[]], [[1, 2]], {"a": 1}, [{"b": 2}], {"__strings__": [[1]]}])
def test_a_model_file_value_its_writer_cannot_write_is_refused(tmp_path, value):
    """A JSON value that a saved model never holds (a nested list, an object) is a ModelFileError at
    load, not a model that loads and then cannot be saved again."""
    det = novelty.make("gmm", n_components=1).fit(np.random.default_rng(0).random((30, 3)))
    det.save(tmp_path / "m.npz")
    entries = read_entries(tmp_path / "m.npz")
    meta = meta_of(entries)
    meta["root"]["values"]["n_iter_"] = value
    bad = write_entries(tmp_path / "bad.npz", with_meta(entries, meta))
    with pytest.raises(ModelFileError, match=r"n_iter_|Unexpected object"):
        novelty.load(bad)


def test_a_count_of_iterations_must_be_an_int(tmp_path):
    det = novelty.make("gmm", n_components=1).fit(np.random.default_rng(0).random((30, 3)))
    det.save(tmp_path / "m.npz")
    entries = read_entries(tmp_path / "m.npz")
    meta = meta_of(entries)
    meta["root"]["values"]["n_iter_"] = [1, 2]
    with pytest.raises(ModelFileError, match=r"n_iter_ must be an int"):
        novelty.load(write_entries(tmp_path / "bad.npz", with_meta(entries, meta)))
