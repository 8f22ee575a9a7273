"""A run stops when the user presses Ctrl-C or the process gets SIGTERM/SIGINT, what it was asked to
save is written, and nothing outlives yadew: YADE itself (a blocking O.run(n, True) stops on
SIGINT), a VTK recorder's last frame (viscbridge.vtk), and yadew's supervision of the command
(tools/supervise.bash) with the real init of its PID namespace (tools/namespace-init.sh), run here
with the root being / (unshare works inside the environment)."""
import os
import signal
import subprocess
import sys
import time
import uuid

import pytest

TOOLS = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'tools')
LONG_RUN = '''
import sys
from yade import O, utils
import viscbridge
O.bodies.append([utils.wall(0, axis=2), utils.sphere((0, 0, 0.6e-3), 0.5e-3)])
O.engines = viscbridge.engines(viscosity=100.0)
print('running', flush=True)
O.run(10**9, True)
print('the run finished', flush=True)
'''


RECORDED_RUN = '''
import signal, sys, time
from yade import O, utils
import viscbridge, viscbridge.vtk as vtk
O.bodies.append([utils.wall(0, axis=2), utils.sphere((0, 0, 0.6e-3), 0.5e-3)])
O.engines = viscbridge.engines(viscosity=100.0)
O.engines = O.engines + [vtk.bridge_recorder(sys.argv[1], iterPeriod=10**8)]
if sys.argv[2] == 'own-handler':  # set after the recorder, as examples/settling.py does
    def terminated(signum, frame):
        raise KeyboardInterrupt('SIGTERM')
    signal.signal(signal.SIGTERM, terminated)
print('running', flush=True)
try:
    O.run(10**9, True)
except KeyboardInterrupt as stop:
    while O.subStep >= 0:  # the step in progress ends after O.run has returned
        time.sleep(0.01)
    print('stopped at step', O.iter, flush=True)
    sys.exit(143 if str(stop) == 'SIGTERM' else 130)
'''


def processes_with(token):
    """Pids of processes whose command line contains `token`."""
    found = []
    for pid in filter(str.isdigit, os.listdir('/proc')):
        try:
            with open('/proc/%s/cmdline' % pid, 'rb') as fh:
                if token.encode() in fh.read():
                    found.append(int(pid))
        except OSError:
            pass
    return found


def wait_gone(token, timeout):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if not processes_with(token):
            return True
        time.sleep(0.1)
    return False


@pytest.fixture
def long_run(tmp_path):
    path = tmp_path / 'long_run.py'
    path.write_text(LONG_RUN)
    return str(path)


def wait_for_line(proc, text, timeout=120):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        line = proc.stdout.readline()
        if text in line:
            return
        assert line or proc.poll() is None, 'the process ended before printing %r' % text
    raise AssertionError('no %r within %g s' % (text, timeout))


def test_sigint_stops_a_blocking_run(long_run):
    """YADE's O.run(n, True) waits in C++; the plugin's SIGINT watcher pauses the loop, so Python
    raises KeyboardInterrupt at once instead of after 10⁹ steps."""
    proc = subprocess.Popen(['yade', '-n', '-x', long_run], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_for_line(proc, 'running')
    time.sleep(1)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=30)
    assert 'KeyboardInterrupt' in err
    assert 'the run finished' not in out
    assert proc.returncode != 0


def supervised(command, token):
    """bash running `supervise` on an unshare'd PID namespace whose init is namespace-init.sh (the
    root being /), as yadew runs every command; `token` marks every process of the tree.  (Mount
    propagation is left unchanged: inside the environment / is no mount point, and the mount
    namespace yadew made is private already.)"""
    script = ('MODE=root; . %s/supervise.bash; supervise unshare --mount --pid --fork --kill-child --propagation unchanged -- '
              '/bin/sh %s/namespace-init.sh / 0 0 "$PWD" "$@"' % (TOOLS, TOOLS))
    return subprocess.Popen(['bash', '-c', script, 'supervised-' + token] + command, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


@pytest.mark.parametrize('sig,status', [(signal.SIGTERM, 143), (signal.SIGHUP, 129)])
def test_sigterm_and_sighup_end_the_whole_tree(sig, status):
    token = uuid.uuid4().hex
    proc = supervised(['sh', '-c', 'echo started; exec sleep 1000', token], token)
    wait_for_line(proc, 'started')
    proc.send_signal(sig)
    proc.communicate(timeout=30)
    assert proc.returncode == status
    assert wait_gone(token, 10), 'processes outlived the supervisor: %s' % processes_with(token)


def test_sigint_to_the_supervisor_stops_yade(long_run):
    """kill -INT to yadew (no terminal): after a short grace period it is passed on as SIGINT."""
    token = uuid.uuid4().hex
    proc = supervised(['yade', '-n', '-x', long_run, token], token)
    wait_for_line(proc, 'running')
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert 'KeyboardInterrupt' in err and 'the run finished' not in out
    assert proc.returncode != 0
    assert wait_gone(token, 10), processes_with(token)


def test_nothing_outlives_a_killed_supervisor():
    """SIGKILL cannot be handled: the command dies with its supervisor (parent-death signal), and
    with the namespace's init everything inside."""
    token = uuid.uuid4().hex
    proc = supervised(['sh', '-c', 'echo started; sleep 1000; echo never', token], token)
    wait_for_line(proc, 'started')
    proc.kill()
    proc.wait(timeout=10)
    assert wait_gone(token, 10), processes_with(token)


def test_exit_status_is_passed_through():
    proc = supervised(['sh', '-c', 'exit 7', 'x'], uuid.uuid4().hex)
    proc.communicate(timeout=60)
    assert proc.returncode == 7


def pvd_steps(path):
    """The step of each data set of a .pvd collection, in its order."""
    import xml.etree.ElementTree as ET
    return [int(d.get('file')[-14:-4]) for d in ET.parse(path).getroot().iter('DataSet')]


@pytest.mark.parametrize('sig,handler,status', [(signal.SIGINT, 'python', 130), (signal.SIGTERM, 'default', -signal.SIGTERM),
                                                (signal.SIGTERM, 'own-handler', 143)])
def test_a_stopped_run_keeps_its_last_vtk_frame(sig, handler, status, tmp_path):
    """A recorder whose period never comes: Ctrl-C, SIGTERM with its default action (the process
    ends by the signal) and SIGTERM handled by the script all leave the frame of the state the run
    stopped in, listed once in every collection."""
    script = tmp_path / 'recorded.py'
    script.write_text(RECORDED_RUN)
    prefix = str(tmp_path / 'out' / 'wet-')
    proc = subprocess.Popen(['yade', '-n', '-x', str(script), prefix, handler], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    wait_for_line(proc, 'running')
    time.sleep(1)
    proc.send_signal(sig)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == status, err[-2000:]
    for kind in ('bridges', 'particles', 'boundary'):
        steps = pvd_steps(prefix + kind + '.pvd')
        assert len(steps) == 2 and steps[0] == 0 < steps[1], (kind, steps)
        assert os.path.isfile(prefix + '%s.%010d.vtp' % (kind, steps[1]))
        if handler != 'default':
            assert 'stopped at step %d' % steps[1] in out


def test_a_run_stopped_by_an_exception_keeps_its_last_vtk_frame(tmp_path):
    """An engine throws in step 7 (as the guard does when it stops a run) and the script ends on the
    exception: the frame of the state it stopped in is written at the exit."""
    script = tmp_path / 'failing.py'
    script.write_text('''
import sys
from yade import O, utils
import yade.wrapper as yw
import viscbridge, viscbridge.vtk as vtk
O.bodies.append([utils.wall(0, axis=2), utils.sphere((0, 0, 0.6e-3), 0.5e-3)])
fail = yw.PyRunner(iterPeriod=1, command='import yade\\nif yade.O.iter == 7: raise RuntimeError("stopped")')
O.engines = [fail] + viscbridge.engines(viscosity=100.0)
O.engines = O.engines + [vtk.bridge_recorder(sys.argv[1], iterPeriod=10**8)]
O.run(100, True)
''')
    prefix = str(tmp_path / 'out' / 'wet-')
    proc = subprocess.run(['yade', '-n', '-x', str(script), prefix], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1 and 'stopped' in proc.stderr, proc.stderr[-2000:]
    assert pvd_steps(prefix + 'bridges.pvd') == [0, 7]
