"""The errors of a scan, reported by the command line as one line each."""
from .cases import _describe, case_key

__all__ = ['ScanError', 'CasesFailed']


class ScanError(Exception):
    """A scan that cannot go on (missing directory or table, ...): reported as one line."""


class CasesFailed(ScanError):
    """Some cases of a run left no result; `failed` lists (case, error message)."""

    def __init__(self, failed, scan_dir):
        self.failed = failed
        lines = ['%d case(s) failed (logs: %s/case-KEY.log; running the scan again retries them):'
                 % (len(failed), scan_dir)]
        lines += ['  %s %s: %s' % (case_key(c), _describe(c), error) for c, error in failed]
        super().__init__('\n'.join(lines))
