"""pytest set-up of the system tier (tests/system): what a user runs, in separate processes —
examples, the documents' snippets, stopping a run (Ctrl-C, SIGTERM), MPI ranks, the scan's command
line and its yade-batch runs, OpenMP threads, the plugin loading in `yade`.

Helpers: yadeproc.py runs a script as its own `yade` process, mpi_case.py is the MPI scene.  YADE is
not booted here; a test that needs a scene in this process (a bed to hand to the processes) imports
it itself.  Every file of this tier is in the slow tier (tests/CMakeLists.txt).
"""
