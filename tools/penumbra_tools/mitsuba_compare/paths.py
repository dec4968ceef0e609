"""Where the comparison finds Penumbra's programs, keeps its work files and writes its
report; and its progress log (stderr, so the report on stdout stays clean)."""
import os
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
TOOLS = os.path.join(ROOT, "tools")
ENTRY = os.path.join(TOOLS, "mitsuba", "mitsuba_compare.py")  # also the Mitsuba worker's program
PENUMBRA = os.path.join(ROOT, "build", "penumbra")
PENUMBRA_BENCH = os.path.join(ROOT, "build", "penumbra_bench")
WORK = os.path.join(ROOT, "build", "mitsuba-compare")
DOC = os.path.join(ROOT, "docs", "PERFORMANCE.md")
INSTALL_HINT = ("run tools/bench/bench-mitsuba (it makes build/venv-mitsuba with mitsuba 3.9.1 and numpy, "
                "and installs libllvm19)")


def log(*a):
    print(*a, file=sys.stderr, flush=True)
