"""Running a scan's cases through yade-batch (:func:`run_cases`): the cases not yet in
``results.jsonl``, `jobs` at a time, with progress, signals (Ctrl-C, SIGTERM, SIGHUP stop yade-batch
and its jobs, a process group of their own) and the failed cases read from their logs.
"""
import contextlib
import os
import re
import signal
import subprocess
import sys
import threading
import time

from .cases import case_key, unique_cases
from .errors import CasesFailed
from .results import ResultsFile
from .table import JOB_SCRIPT, write_table

__all__ = ['run_cases']


def run_cases(cases, scan_dir, jobs=2, progress=True):
    """Run every case not yet in scan_dir/results.jsonl, `jobs` at a time, through yade-batch.
    Returns the list of all results (old and new).

    scan_dir/cases.table gets the whole scan (what :func:`slurm_script` submits), scan_dir/todo.table
    the cases still to run (what yade-batch runs).  Raises CasesFailed when cases left no result or
    yade-batch reports them failed; KeyboardInterrupt (also on SIGTERM or SIGHUP) once yade-batch and
    its jobs are stopped."""
    if not (isinstance(jobs, int) and jobs >= 1):
        raise ValueError('run_cases: jobs=%r is out of range; allowed: integer >= 1' % (jobs,))
    cases = unique_cases(cases)
    scan_dir = os.path.abspath(scan_dir)
    os.makedirs(scan_dir, exist_ok=True)
    write_table(cases, os.path.join(scan_dir, 'cases.table'), scan_dir)
    results = ResultsFile(os.path.join(scan_dir, 'results.jsonl'))
    done = results.done_keys()
    todo = [c for c in cases if case_key(c) not in done]
    if progress:
        print('scan: %d cases, %d already done, %d to run' % (len(cases), len(cases) - len(todo), len(todo)), file=sys.stderr)
    if todo:
        reported = _run_batch(write_table(todo, os.path.join(scan_dir, 'todo.table'), scan_dir), scan_dir, jobs,
                              _progress(len(todo)) if progress else None, lambda: len(results.done_keys() - done))
        failed = _failures(todo, results.done_keys(), reported, scan_dir)
        if failed:
            raise CasesFailed(failed, scan_dir)
    return results.read()


def _run_batch(table, scan_dir, jobs, bar, finished):
    """Run yade-batch on `table`; returns the descriptions (case keys) of the jobs it reports failed."""
    # per-case logs beside the results (yade-batch's default puts them beside the job script,
    # inside the installed package); relative, since yade-batch runs in scan_dir
    cmd = ['yade-batch', '--job-threads=1', '-j', str(jobs), '--log', 'case-@.log', table, JOB_SCRIPT]
    log_path = os.path.join(scan_dir, 'yade-batch.log')
    with open(log_path, 'ab') as log:
        start = log.tell()  # the log is appended to by every run: this run's part starts here
        # its own session: Ctrl-C in a terminal reaches this process only, which stops the whole
        # group (yade-batch and its jobs) and then reports
        proc = subprocess.Popen(cmd, cwd=scan_dir, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        try:
            with interruptible():
                while proc.poll() is None:
                    time.sleep(2)
                    if bar:
                        bar(finished())
        finally:
            if proc.returncode is None:
                with _signals(signal.SIG_IGN):  # a second Ctrl-C must not leave the jobs running
                    _stop_group(proc)
            if bar:
                bar(finished(), final=True)
    with open(log_path, 'rb') as fh:
        fh.seek(start)
        output = fh.read().decode(errors='replace')
    return set(re.findall(r'^#\d+ \((\w+)\) FAILED', output, re.M))


def _interrupt(signum, frame):
    raise KeyboardInterrupt(signal.Signals(signum).name)


def interruptible():
    """Within: SIGTERM and SIGHUP raise KeyboardInterrupt, as Ctrl-C does, so that a command
    stopped by any of them reports it and keeps what finished (the scan's command line wraps a whole
    command in it: a signal just after yade-batch ended used to kill it without a word)."""
    return _signals(_interrupt)


@contextlib.contextmanager
def _signals(handler):
    """Within: SIGINT, SIGTERM and SIGHUP go to `handler` unless ignored (only the main thread can
    set handlers)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)}
    for s, h in old.items():
        if h is not signal.SIG_IGN:  # an ignored signal stays ignored (nohup, a background job)
            signal.signal(s, handler)
    try:
        yield
    finally:
        for s, h in old.items():
            signal.signal(s, signal.SIG_DFL if h is None else h)


def _stop_group(proc, grace=5.0):
    """Stop yade-batch and the jobs it started (its process group): SIGTERM, then SIGKILL for
    whatever outlives `grace` seconds."""
    os.killpg(proc.pid, signal.SIGTERM)
    deadline = time.monotonic() + grace
    # wait without reaping: while yade-batch is not reaped its group id cannot be taken by another
    while time.monotonic() < deadline and os.waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is None:
        time.sleep(0.1)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


def _failures(todo, done, reported, scan_dir):
    """(case, error) for each case of `todo` without a result or reported failed by yade-batch."""
    failed = []
    for c in todo:
        key = case_key(c)
        if key not in done or key in reported:
            error = _log_error(os.path.join(scan_dir, 'case-%s.log' % key))
            failed.append((c, error if key not in done else 'wrote its result, then failed: ' + error))
    return failed


def _log_error(path):
    """The error a case log ends with: the message of an engine's exception as YADE printed it (the
    line after "Exception occured:"; when YADE's O.wait() missed it, the Python error only says the
    run stopped short); else its last Python exception line; else the last line before yade-batch's
    job summary."""
    if not os.path.exists(path):
        return 'not started (no %s; see yade-batch.log)' % os.path.basename(path)
    with open(path, errors='replace') as fh:
        lines = [line.strip() for line in fh if line.strip()]
    end = next((k for k, line in enumerate(lines) if 'JOB SUMMARY' in line), len(lines))
    lines, summary = lines[:end], lines[end:]
    errors = [line for line in lines if re.match(r'[\w.]*(Error|Exception|Interrupt)\b', line)]
    engine_errors = [after for line, after in zip(lines, lines[1:]) if line.endswith('Exception occured:')]
    if errors or engine_errors:
        return (engine_errors or errors)[-1]
    status = [line.split(':', 1)[1].strip() for line in summary if line.startswith('status')]
    return '%s (no error in its log; yade-batch status %s)' % ((lines or ['an empty log'])[-1], (status or ['unknown'])[0])


def _progress(total):
    try:
        from tqdm import tqdm
        bar = tqdm(total=total, unit='case', file=sys.stderr)

        def update(n, final=False):
            bar.update(n - bar.n)
            if final:
                bar.close()
        return update
    except ImportError:
        def update(n, final=False):
            print('scan: %d/%d cases done' % (n, total), file=sys.stderr)
        return update
