"""What a documentation block prints, against what its comments say it prints.

A page shows output in one of three ways, and ``tests/test_docs.py`` checks each:

- a ``print`` line's trailing comment begins with what the line printed
  (``print(round(x, 4))   # 0.0534: a familiar scan``; the prose after it is
  not compared). A line printed several times, in a loop, is compared with
  everything it printed, joined by spaces;
- comment lines directly below a ``print`` are its output, a line each
  (``# 10.0 [1.0, 3.0] [0.0, 0.0, 0.0] 1.0``), compared whole;
- a ``text`` block marked ``<!-- printed by the block above -->`` is the whole
  output of the block before it, compared whole.

The tolerance: words and punctuation are equal (spaces aside); a number
written with a decimal point or an exponent may be the printed number
rounded to the digits it shows (``0.6997`` for ``0.69970001``: half a unit
of its last digit), a number without is equal to the printed one.
A trailing comment that begins with a value (a bracket, a quote, ``True``,
``False``, ``None``, or a number not followed by a word: ``# 0.5``, not
``# 6 beams``) on a line that is not a ``print`` would be an output nobody
checks: the line must print it.
"""

from __future__ import annotations

import ast
import io
import re
import tokenize
from dataclasses import dataclass

#: runs a block file as ``python -c`` would, recording each print to stdout with the block's line
#: that made it: ``python -c WRAPPER block.py record.json``
WRAPPER = r'''
import atexit, builtins, json, sys
_docs_block, _docs_record = sys.argv[1:3]
sys.argv = ["-c"]
_docs_said, _docs_print = [], builtins.print

def _docs_recording_print(*args, sep=" ", end="\n", file=None, flush=False):
    if file is None or file is sys.stdout:
        frame = sys._getframe(1)
        while frame is not None and frame.f_code.co_filename != _docs_block:
            frame = frame.f_back
        text = (" " if sep is None else sep).join(map(str, args)) + ("\n" if end is None else end)
        _docs_said.append([None if frame is None else frame.f_lineno, text])
    _docs_print(*args, sep=sep, end=end, file=file, flush=flush)

def _docs_write():
    with open(_docs_record, "w", encoding="utf-8") as fh:
        json.dump(_docs_said, fh)

builtins.print = _docs_recording_print
atexit.register(_docs_write)
with open(_docs_block, encoding="utf-8") as _docs_fh:
    _docs_code = compile(_docs_fh.read(), _docs_block, "exec")
del _docs_fh
exec(_docs_code)
'''

#: a number (a sign only where it cannot be a dash between words or numbers), a word, or one other character
_TOKEN = re.compile(r"(?P<num>(?<![\w.)\]])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?)|(?P<word>\w+)|(?P<other>\S)")
#: a comment that begins with a value, an output if anything: a bracket, a quote, True, False, None, or a
#: number not followed by a word ("# 0.5", "# 1.0: new", "# [0, 1]"; not "# 6 beams over 180 degrees")
_VALUE = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?(?!\s*[A-Za-z_]|[\w.])|[\[({'\"]|(?:True|False|None)\b")


@dataclass
class Claim:
    """What the comments of one ``print`` say it prints."""

    first: int          # the print's lines, first and last
    last: int
    text: str           # the comment (trailing) or the comment lines below (joined by newlines)
    whole: bool         # comment lines: compared whole; a trailing comment: its beginning


def _tokens(text: str) -> list[tuple[str, str]]:
    return [(m.lastgroup, m.group()) for m in _TOKEN.finditer(text)]


def _number_matches(written: str, printed: str) -> bool:
    value, shown = float(written), float(printed)
    mantissa, _, exponent = written.lower().partition("e")
    if "." not in mantissa and not exponent:
        return value == shown
    decimals = len(mantissa.partition(".")[2]) - int(exponent or 0)
    return abs(value - shown) <= 0.5 * 10.0 ** -decimals * (1 + 1e-9)


def _same(written: tuple[str, str], printed: tuple[str, str]) -> bool:
    if written[0] == printed[0] == "num":
        return _number_matches(written[1], printed[1])
    return written == printed


def differs(written: str, printed: str, prose_after: bool = False) -> bool:
    """Whether ``written`` (a comment) misstates ``printed``, within the tolerance above.

    With ``prose_after``, ``written`` need only begin with the printed text.

    >>> differs("0.6997: then familiar", "0.69970001", prose_after=True)
    False
    >>> differs("1.0: a first perception", "0.0534", prose_after=True)
    True
    >>> differs("[1, 1, 1] 3", "[1, 1, 1] 3"), differs("4", "4.5"), differs("0.7", "0.70000001")
    (False, True, False)
    """
    want, got = _tokens(written), _tokens(printed)
    if len(want) < len(got) or (len(want) > len(got) and not prose_after):
        return True
    return not all(_same(w, g) for w, g in zip(want, got))


def differs_by_line(written: str, printed: str) -> bool:
    """Whether ``written`` misstates ``printed`` line by line (blank lines at either end aside)."""
    want, got = (text.strip("\n").splitlines() for text in (written, printed))
    return len(want) != len(got) or any(differs(w, g) for w, g in zip(want, got))


def _comments(code: str) -> dict[int, tuple[str, bool]]:
    """``{line: (comment text, whether the line holds only the comment)}``."""
    found = {}
    lines = code.splitlines()
    for tok in tokenize.generate_tokens(io.StringIO(code).readline):
        if tok.type == tokenize.COMMENT:
            row, col = tok.start
            found[row] = (tok.string[1:].strip(), not lines[row - 1][:col].strip())
    return found


def _prints(tree: ast.AST) -> list[ast.Call]:
    """The calls of ``print`` that write to standard output."""
    return [node for node in ast.walk(tree)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "print"
            and not any(k.arg == "file" for k in node.keywords)]


def claims(code: str) -> list[Claim]:
    """Each commented ``print`` of a Python block and what its comments say it prints."""
    comments = _comments(code)
    found = []
    for call in _prints(ast.parse(code)):
        trailing = [comments[n][0] for n in range(call.lineno, call.end_lineno + 1)
                    if n in comments and not comments[n][1]]
        if trailing:
            found.append(Claim(call.lineno, call.end_lineno, trailing[0], whole=False))
            continue
        below, n = [], call.end_lineno + 1
        while n in comments and comments[n][1]:
            below.append(comments[n][0])
            n += 1
        if below:
            found.append(Claim(call.lineno, call.end_lineno, "\n".join(below), whole=True))
    return found


def unprinted_values(code: str) -> list[str]:
    """Trailing comments that state a value on lines that print nothing: outputs no test would check."""
    printing = {n for call in _prints(ast.parse(code)) for n in range(call.lineno, call.end_lineno + 1)}
    return [f"line {n}: # {text}" for n, (text, alone) in sorted(_comments(code).items())
            if not alone and n not in printing and _VALUE.match(text)]


def misstatements(code: str, said: list[tuple[int | None, str]]) -> tuple[list[str], str]:
    """What the comments of ``code`` misstate about what it printed (``said``: (line, text) of each
    print, as the wrapper records them), and the printed text no comment speaks for."""
    wrong, claimed = [], set()
    for claim in claims(code):
        printed = "".join(text for line, text in said if line is not None and claim.first <= line <= claim.last)
        claimed.update(range(claim.first, claim.last + 1))
        bad = (differs_by_line(claim.text, printed) if claim.whole
               else differs(claim.text, " ".join(printed.split()), prose_after=True))
        if bad:
            wrong.append(f"line {claim.first}: the comment says {claim.text!r}, the line printed {printed!r}")
    unclaimed = "".join(text for line, text in said if line not in claimed)
    return wrong, unclaimed
