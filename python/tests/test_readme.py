"""The README's "From Python" section runs as written: its Python blocks,
in order, in one namespace, in a clean folder holding a copy of configs/;
its shell lines are run elsewhere (tests/integration/readme.rs names where:
the install by .ci/run, from the wheel; the porosity study by test_examples.py)."""

from __future__ import annotations

import contextlib
import io
import re

from conftest import ROOT


def section() -> str:
    text = (ROOT / "README.md").read_text()
    start = text.index("\n## From Python\n")
    end = text.index("\n## ", start + 1)
    return text[start:end]


def blocks(text: str, language: str) -> list:
    return re.findall(rf"^```{language}\n(.*?)^```$", text, flags=re.M | re.S)


def test_the_python_blocks_run_and_print_what_they_say(work):
    code = blocks(section(), "python")
    assert len(code) >= 2
    printed = io.StringIO()
    namespace: dict = {}
    with contextlib.redirect_stdout(printed):
        for block in code:
            exec(compile(block, "README.md (From Python)", "exec"), namespace)
    out = printed.getvalue().splitlines()
    # What the comments say the lines print.
    assert out[0] == "<gapack.Packing pack: 2483 disks, porosity 0.2013, seed 3>"
    assert out[1].startswith("0.2012") and out[1].endswith(" rectangle")
    assert out[2] == "valid"
    assert any(line.startswith("reached 0.498") for line in out)
    assert out[-1] == "domain.width 3 9"
    assert (work / "out" / "sq-py" / "packing.lammps").is_file()
    assert (work / "out" / "sq-py" / "packing.vtk").is_file()


def test_the_shell_lines_have_a_place():
    lines = [l for b in blocks(section(), "sh") for l in b.splitlines() if l.strip()]
    assert lines, "the section shows how to install"
    elsewhere = (ROOT / "tests" / "integration" / "readme.rs").read_text()
    for line in lines:
        start = line.split("#")[0].strip()
        assert any(
            start.startswith(known) for known in re.findall(r'\(\s*"([^"]+)",', elsewhere)
        ), f"tests/integration/readme.rs does not say where `{start}` runs"
