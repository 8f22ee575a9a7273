"""ViscBridge: DEM of wet particles held together by highly viscous liquid bridges, for YADE.

Import inside YADE (``./yadew run``, ``./yadew console``, or any yade session with the plugin
installed).  The C++ classes (``Ip2_FrictMat_FrictMat_ViscBridgePhys``,
``Law2_ScGeom_ViscBridgePhys_HertzViscous``, ...) are registered in ``yade.wrapper`` like YADE's
own; this package adds the Python tools around them.
"""
import os
import sys

__all__ = ['plugin_path', 'yade_version', 'engines', 'agglomerates']

# Modules that need a running YADE are imported on first use, so that the planning tools
# (viscbridge.criteria) work in plain Python.
_LAZY = {'engines': ('engine_list', 'engines'), 'agglomerates': ('analysis.agglomerates', 'agglomerates')}


def __getattr__(name):
    if name in _LAZY:
        import importlib
        module, attr = _LAZY[name]
        value = getattr(importlib.import_module('.' + module, __name__), attr)
        globals()[name] = value
        return value
    raise AttributeError('module %r has no attribute %r' % (__name__, name))


def yade_version():
    """Version of the running YADE, or None when YADE is not loaded in this interpreter.

    YADE is never imported from here: ``viscbridge.criteria`` must stay usable in plain Python.
    """
    if 'yade' not in sys.modules:
        return None
    from yade import config
    return config.version


def plugin_path():
    """Path of the loaded ``libpkg_viscbridge.so`` (raises RuntimeError when YADE has not loaded it)."""
    from yade import config
    for root, _dirs, files in os.walk(config.libDir):
        if 'libpkg_viscbridge.so' in files:
            return os.path.join(root, 'libpkg_viscbridge.so')
    raise RuntimeError('libpkg_viscbridge.so is not in YADE\'s library directory %s; run YADE through '
                       './yadew, or install the plugin (cmake --install build)' % config.libDir)


def _check_plugin():
    """The plugin must have been compiled against the headers of the running YADE."""
    import yade.wrapper
    if not hasattr(yade.wrapper, 'ViscBridgeHeaderProbe'):
        return  # plain Python without the plugin: the pure-Python tools still work
    built = yade.wrapper.ViscBridgeHeaderProbe().yadeVersion
    if built != yade_version():
        raise ImportError('libpkg_viscbridge.so was built against YADE %s headers but YADE %s is '
                          'running; rebuild it (./yadew build)' % (built, yade_version()))


if yade_version() is not None:
    _check_plugin()
    from . import _attribute_types
    _attribute_types.install()
