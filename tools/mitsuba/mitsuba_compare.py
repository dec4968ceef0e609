#!/usr/bin/env python3
"""Penumbra vs Mitsuba 3 on the same machine: throughput, start-up, image agreement and
time-to-error for the benchmark scenes. Run it through tools/bench/bench-mitsuba, which makes the
Python environment it needs (build/venv-mitsuba: mitsuba 3.9.1, numpy; Debian's libllvm19).

  tools/bench/bench-mitsuba [--runs 5] [--scenes A.json B.json ...] [--quick] [--no-doc]

Per scene:
  * Penumbra: `build/penumbra render` --runs times at the scene's spp; render time is the
    EXR header's penumbra:render_seconds (median), start-up is wall time minus render time.
  * Mitsuba llvm_ad_rgb and scalar_rgb, each in a fresh process: scene load, first render
    (JIT compilation for llvm) reported as start-up, then the median of --runs renders
    (scalar: --scalar-runs, and fewer spp where Python plugins make it slow).
  * Agreement (at --quality-scale of the film size): a Penumbra reference of --ref-spp is
    compared with a Mitsuba llvm render of the same spp (relMSE, relMSE of 8x8 block
    means, per-channel mean ratio, worst block), next to the noise floor: two independent
    Mitsuba renders of that spp compared with each other.
  * Time-to-error (Cornell box and MIS scene): renders at 1, 2, 4, ... spp until the relMSE
    against the Penumbra reference drops below --target; each level's time is the median of
    --tte-runs (3) renders of the same image, and the time at the target is interpolated
    log-log between the two bracketing levels. Penumbra with its Sobol'
    default and with the independent sampler; Mitsuba llvm with independent and ldsampler.
Writes a markdown report to stdout and into docs/PERFORMANCE.md (section "Results").
The code is in tools/penumbra_tools/mitsuba_compare/, one module per concern.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))  # tools/: penumbra_tools
from penumbra_tools.mitsuba_compare.cli import main

if __name__ == "__main__":
    main(__doc__)
