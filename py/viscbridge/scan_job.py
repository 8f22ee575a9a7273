# The job script under its path before viscbridge.scan became a package: scan.sbatch files written
# then run `yade -n -x .../py/viscbridge/scan_job.py`, so they can still be resubmitted.  The job
# itself is viscbridge/scan/job.py (viscbridge.scan.JOB_SCRIPT).
from viscbridge.scan.job import main

main()
