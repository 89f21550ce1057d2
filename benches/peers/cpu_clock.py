#!/usr/bin/env python
"""Run a benchmark script with `time.perf_counter` replaced by `time.process_time`.

    python cpu_clock.py SCRIPT.py ARGS...

The script's timings then count the CPU time of the whole process (every thread)
instead of wall time, which leaves out the time it waited for a core on a machine
shared with other jobs. Used by run_side_by_side.sh with CLOCK=cpu; works for the
peer-engine scripts (read-only, used as they are) and for ours.
"""
import os
import runpy
import sys
import time

if len(sys.argv) < 2:
    sys.exit(__doc__)
time.perf_counter = time.process_time
script = sys.argv[1]
sys.argv = sys.argv[1:]
sys.path.insert(0, os.path.dirname(os.path.abspath(script)))
runpy.run_path(script, run_name="__main__")
