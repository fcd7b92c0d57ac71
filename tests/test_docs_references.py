"""The repository stands alone: no tracked text file points a reader at a document that is
not in it.

Three kinds of dangling reference are looked for in every tracked text file (``git
ls-files``; the working tree when this is not a git checkout):

- the project's private working notes, which never ship with the repository (a model
  specification, an architecture note and a property-facts note, by their file names) and
  the folder that held them;
- "issue N": an issue tracker the reader cannot see; write what the issue asked instead;
- repository paths (``tests/<name>.py``, ``benchmarks/<name>.py``, ``docs/<name>.md``) that do not
  exist, such as a test module that was renamed (paths with an ``output`` folder are what
  a script writes, and are not checked).

Each failure names the file and the line. The patterns below are assembled from pieces so
that this file does not match itself.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

#: Suffixes of the files scanned.
TEXT_SUFFIXES = {".py", ".md", ".toml", ".txt", ".rst", ".cfg", ".yml", ".yaml"}

_NOTE = "|".join(("MODEL", "ARCHITECTURE", "PROPERTIES"))
#: Documents outside the repository, and "issue N".
OUTSIDE = [
    (re.compile(r"\b(?:" + _NOTE + r")\.md\b"), "a working note outside the repository"),
    (re.compile(r"\.\./" + "shared" + r"\b"), "a folder outside the repository"),
    (re.compile(r"/work/" + "shared" + r"\b"), "a folder outside the repository"),
    (re.compile(r"\b" + "issue" + r"s?\s+(?:item\s+)?#?\d+", re.IGNORECASE),
     "an issue number the reader cannot look up"),
]

#: Repository-relative paths of files (with a suffix); ``*`` allowed as a glob.
_PATH = re.compile(
    r"(?<![\w./-])((?:tests|benchmarks|docs|examples|materials|agglomtool)"
    r"/[\w.*/-]*\.(?:py|md|toml|csv|png|json|txt|rst|cfg|yml))\b"
)


def tracked_text_files() -> list[Path]:
    """Tracked files with a text suffix (all files under ROOT outside .git without git)."""
    try:
        out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True,
                             check=True).stdout.decode()
        names = [n for n in out.split("\0") if n]
    except (OSError, subprocess.CalledProcessError):
        names = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*")
                 if p.is_file() and ".git" not in p.parts]
    return sorted(ROOT / n for n in names
                  if Path(n).suffix in TEXT_SUFFIXES and (ROOT / n).is_file())


def scan_outside(path: Path) -> list[str]:
    """``file:line: what`` for every reference to an outside document in ``path``."""
    hits = []
    text = path.read_text(encoding="utf-8", errors="replace")
    for number, line in enumerate(text.splitlines(), start=1):
        for pattern, what in OUTSIDE:
            m = pattern.search(line)
            if m:
                hits.append(f"{path.relative_to(ROOT)}:{number}: {what}: {m.group(0)!r}")
    return hits


def scan_paths(path: Path) -> list[str]:
    """``file:line: path`` for every repository path in ``path`` that matches no file."""
    hits = []
    text = path.read_text(encoding="utf-8", errors="replace")
    for number, line in enumerate(text.splitlines(), start=1):
        for m in _PATH.finditer(line):
            ref = m.group(1)
            if "output" in Path(ref).parts:  # where a script writes, not a file it reads
                continue
            if not any(ROOT.glob(ref)):
                hits.append(f"{path.relative_to(ROOT)}:{number}: no such file: {ref}")
    return hits


FILES = tracked_text_files()


def test_files_are_found():
    """The scan is not vacuous: it sees the package, the tests and the documentation."""
    names = {str(p.relative_to(ROOT)) for p in FILES}
    assert "agglomtool/api.py" in names and "README.md" in names
    assert "tests/conftest.py" in names and "materials/README.md" in names


def test_no_reference_to_documents_outside_the_repository():
    hits = [h for p in FILES for h in scan_outside(p)]
    assert not hits, "references outside the repository:\n" + "\n".join(hits)


def test_repository_paths_exist():
    hits = [h for p in FILES for h in scan_paths(p)]
    assert not hits, "references to files that do not exist:\n" + "\n".join(hits)


@pytest.mark.parametrize(
    ("line", "found"),
    [
        ("see " + "MODEL" + ".md section 4", True),
        ("as in " + "../" + "shared/reference", True),
        ("Tolerance 1 % (" + "issue" + " 3): rounding", True),
        ("(" + "issue" + " item 2, grids)", True),
        ("the paper's Eq. 94 (Pitois et al. 2001)", False),
        ("an issue of the tool", False),
        ("docs/model.md, section 'Corrections'", False),
    ],
)
def test_patterns(tmp_path, line, found):
    """The patterns catch the forms met in this repository and pass ordinary prose."""
    f = tmp_path / "probe.md"
    f.write_text(f"first line\n{line}\n", encoding="utf-8")
    hits = []
    for pattern, _ in OUTSIDE:
        hits += [pattern.search(t) for t in f.read_text().splitlines()]
    assert any(h is not None for h in hits) == found
