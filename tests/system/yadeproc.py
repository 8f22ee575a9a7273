"""Run a script as a separate `yade` process, for tests where isolation matters (a crash, global
state, threads, saving and loading).  The script reports back by writing JSON to the path in the
environment variable VISCBRIDGE_RESULT."""
import json
import os
import subprocess
import tempfile


def run_yade(script, *args, threads=1, timeout=600, env=None, check=True, cwd=None):
    """Run ``yade -n -x [-jN] script args`` and return (completed_process, result_dict_or_None).

    ``script`` is a path, or source text (anything containing a newline) written to a temp file;
    ``cwd``: the working directory (default: a temporary one).
    """
    with tempfile.TemporaryDirectory() as tmp:
        if '\n' in script:
            path = os.path.join(tmp, 'script.py')
            with open(path, 'w') as fh:
                fh.write(script)
        else:
            path = script
        result = os.path.join(tmp, 'result.json')
        e = dict(os.environ, VISCBRIDGE_RESULT=result, OMP_NUM_THREADS=str(threads), **(env or {}))
        cmd = ['yade', '-n', '-x', '-j%d' % threads, path, *map(str, args)]
        proc = subprocess.run(cmd, env=e, capture_output=True, text=True, timeout=timeout, cwd=cwd or tmp)
        if check and proc.returncode != 0:
            raise AssertionError('yade exited with %d\n--- stdout\n%s\n--- stderr\n%s'
                                 % (proc.returncode, proc.stdout[-4000:], proc.stderr[-4000:]))
        data = None
        if os.path.exists(result):
            with open(result) as fh:
                data = json.load(fh)
        return proc, data
