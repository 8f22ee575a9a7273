"""Which host directories ./yadew shares with the Debian root (bind_set in yadew): a script writes on
the host wherever it points, except in the root's own system directories.  A user's file written
to /var/tmp or /root used to land inside the root, where nobody would look for it."""
import os
import re
import subprocess

YADEW = os.path.join(os.path.dirname(__file__), '..', '..', 'yadew')


def bind_set(*paths):
    """yadew's bind_set (its definition and SYSTEM_DIRS, taken from the script) applied to `paths`."""
    text = open(YADEW).read()
    system = re.search(r"^readonly SYSTEM_DIRS=.*$", text, re.M).group(0)
    function = re.search(r"^bind_set\(\) \{.*?^\}", text, re.M | re.S).group(0)
    out = subprocess.run(['bash', '-c', '%s\n%s\nbind_set "$@"' % (system, function), 'bind_set', *paths],
                         capture_output=True, text=True, check=True)
    return out.stdout.split()


def test_user_directories_are_shared_and_system_ones_are_not():
    assert bind_set('/root', '/home', '/var/tmp', '/srv', '/work/run') == ['/home', '/root', '/srv', '/var/tmp', '/work/run']
    assert bind_set('/', '/usr', '/usr/local/share', '/etc', '/var', '/var/lib/x', '/opt/x', '/proc', '/boot') == []


def test_a_directory_below_a_shared_one_is_covered_by_it():
    assert bind_set('/home/me/run', '/home', '/tmp/a', '/tmp') == ['/home', '/tmp']
    assert bind_set('/var/tmp/me', '/var/tmp') == ['/var/tmp']
