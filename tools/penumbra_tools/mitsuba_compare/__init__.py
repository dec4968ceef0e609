"""Penumbra vs Mitsuba 3 on the same machine: throughput, start-up, image agreement and
time-to-error for the benchmark scenes (tools/bench/bench-mitsuba runs tools/mitsuba/mitsuba_compare.py,
which runs cli.main). One concern per module:

  paths           where the programs, the work folder and the report live; logging
  scenes          reading a Penumbra scene's film, spp and features
  images          EXR input/output and the relMSE of penumbra compare
  penumbra_runs   rendering with build/penumbra: timed renders, references, time-to-error
  mitsuba_worker  one Mitsuba variant in a fresh process, driven by a JSON job
  agreement       do two renderers agree (against the noise floor); time to an error
  report          the markdown report and docs/PERFORMANCE.md
  cli             the command line and the measurement plan per scene
"""
