"""The plugin loads in a `yade` process of its own, the route ./yadew run takes: the running YADE is the
one it was built against, and libpkg_viscbridge.so is found."""
from yadeproc import run_yade


def test_plugin_loads_in_a_separate_yade_process():
    """The same plugin loads in a real `yade -n -x` process (the route ./yadew run takes)."""
    proc, data = run_yade("""
import json, os
import yade
import viscbridge
json.dump({'version': yade.config.version,
           'probe': 'ViscBridgeHeaderProbe' in dir(yade.wrapper),
           'builtAgainst': yade.wrapper.ViscBridgeHeaderProbe().yadeVersion,
           'plugin': viscbridge.plugin_path()}, open(os.environ['VISCBRIDGE_RESULT'], 'w'))
""")
    assert data['version'] == '2025.2.0'
    assert data['probe'] is True
    assert data['builtAgainst'] == '2025.2.0'
    assert data['plugin'].endswith('libpkg_viscbridge.so')
