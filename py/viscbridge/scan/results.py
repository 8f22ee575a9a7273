"""The results of a scan: ``results.jsonl``, one finished case per line, appended atomically by the
jobs (what resuming reads), and ``results.csv`` collected from it.  Plain Python.
"""
import json
import os

from .errors import ScanError

__all__ = ['ResultsFile', 'collect']


class ResultsFile:
    """JSON lines, one finished case per line, appended atomically (safe with parallel jobs)."""

    def __init__(self, path):
        self.path = path

    def append(self, result):
        import fcntl
        line = json.dumps(result, sort_keys=True) + '\n'
        os.makedirs(os.path.dirname(os.path.abspath(self.path)), exist_ok=True)
        with open(self.path, 'a') as fh:
            fcntl.flock(fh, fcntl.LOCK_EX)
            fh.write(line)
            fh.flush()
            os.fsync(fh.fileno())
            fcntl.flock(fh, fcntl.LOCK_UN)

    def read(self):
        if not os.path.exists(self.path):
            return []
        out = []
        with open(self.path) as fh:
            for line in fh:
                line = line.strip()
                if line:
                    try:
                        out.append(json.loads(line))
                    except json.JSONDecodeError:
                        pass  # a line cut by a kill: that case simply runs again
        return out

    def done_keys(self):
        return {r['key'] for r in self.read() if 'key' in r}



def _scan_dir(scan_dir):
    if not os.path.isdir(scan_dir):
        raise ScanError('no such scan directory: %s' % scan_dir)
    return scan_dir


def collect(scan_dir):
    """Write scan_dir/results.csv from results.jsonl (latest result per case) and return the rows."""
    import csv
    rows = {}
    for r in ResultsFile(os.path.join(_scan_dir(scan_dir), 'results.jsonl')).read():
        rows[r.get('key')] = r
    rows = list(rows.values())
    if rows:
        keys = sorted({k for r in rows for k in r})
        with open(os.path.join(scan_dir, 'results.csv'), 'w', newline='') as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(rows)
    return rows
