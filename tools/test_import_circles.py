#!/usr/bin/env python3
"""Tests of tools/import_circles.py on small source trees: it finds a circle between stages, one
within a folder (through a mod.rs), and none where a mod.rs only re-exports its children.

    python3 tools/test_import_circles.py
"""

import subprocess
import sys
import tempfile
from pathlib import Path

TOOL = Path(__file__).resolve().parent / "import_circles.py"


def check(files):
    """Exit code and output of `import_circles.py --check` over a tree of `files` (path → text)."""
    with tempfile.TemporaryDirectory() as d:
        for name, text in files.items():
            path = Path(d) / name
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        r = subprocess.run([sys.executable, TOOL, "--check", "--src", d], capture_output=True, text=True)
        return r.returncode, r.stdout


LIB = "pub mod a;\npub mod b;\n"
CASES = [
    (
        "stages that import each other",
        {"lib.rs": LIB, "a.rs": "use crate::b::B;\npub struct A;\n", "b.rs": "use crate::a::A;\npub struct B;\n"},
        1,
        "circle in the stages under src/: a <-> b",
    ),
    (
        "a stage below another",
        {"lib.rs": LIB, "a.rs": "use crate::b::B;\npub struct A;\n", "b.rs": "pub struct B;\n"},
        0,
        "0 import circle(s)",
    ),
    (
        "a child reaching back into a mod.rs that uses it",
        {
            "lib.rs": "pub mod a;\n",
            "a/mod.rs": "mod x;\nuse x::f;\npub struct Shared;\npub fn g() { f() }\n",
            "a/x.rs": "use super::Shared;\npub fn f() { let _ = Shared; }\n",
        },
        1,
        "circle in src/a: mod.rs <-> x",
    ),
    (
        "a mod.rs that only re-exports",
        {
            "lib.rs": "pub mod a;\n",
            "a/mod.rs": "mod x;\nmod y;\npub use x::f;\npub use y::Shared;\n",
            "a/x.rs": "use super::Shared;\npub fn f() { let _ = Shared; }\n",
            "a/y.rs": "pub struct Shared;\n",
        },
        0,
        "0 import circle(s)",
    ),
    (
        "a use inside a test module or a doc link",
        {
            "lib.rs": LIB,
            "a.rs": "/// See [`crate::b::B`].\npub struct A;\n",
            "b.rs": "use crate::a::A;\npub struct B;\n#[cfg(test)]\nmod tests {\n    use crate::a::A;\n}\n",
        },
        0,
        "0 import circle(s)",
    ),
]

failed = 0
for name, files, code, expected in CASES:
    got, out = check(files)
    ok = got == code and expected in out
    failed += not ok
    print(f"{'ok  ' if ok else 'FAIL'} {name}" + ("" if ok else f": exit {got}, output {out!r}"))
sys.exit(1 if failed else 0)
