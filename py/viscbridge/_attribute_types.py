"""Wrong types on the attributes of ViscBridge's YADE classes name the attribute.

Boost.Python rejects ``Ip2_FrictMat_FrictMat_ViscBridgePhys(viscosity='10')`` with "No registered
converter was able to produce a C++ rvalue of type double ..." and ``ip2.viscosity = '10'`` with
"Python argument types in None.None(...) did not match C++ signature", naming neither the attribute
nor what it takes.  :func:`install` wraps the classes' ``__init__`` and ``__setattr__`` so that the
same mistakes raise TypeError with the class, the attribute, the value and the expected type.  The
C++ checks of values (ValueError naming the allowed range) are untouched.
"""

_BOOST_TYPE_ERRORS = ('did not match C++ signature', 'No registered converter')
_NUMBERS = (int, float)


def _boost_type_error(error):
    return any(text in str(error) for text in _BOOST_TYPE_ERRORS)


def _fits(value, current):
    """Whether `value` has a type the attribute holding `current` takes."""
    if isinstance(current, bool):
        return isinstance(value, (bool, int))
    if isinstance(current, _NUMBERS):
        return isinstance(value, _NUMBERS)
    if isinstance(current, str):
        return isinstance(value, str)
    return True  # vectors, lists, objects: left to Boost's own message


def _wrong_type(cls_name, name, value, current):
    expected = 'a number' if isinstance(current, _NUMBERS) and not isinstance(current, bool) else type(current).__name__
    return TypeError('%s.%s=%r has the wrong type (%s); expected %s (e.g. %r)'
                     % (cls_name, name, value, type(value).__name__, expected, current))


def _wrap(cls):
    original_init, original_setattr = cls.__init__, cls.__setattr__

    def __setattr__(self, name, value):
        try:
            original_setattr(self, name, value)
        except TypeError as error:
            if not _boost_type_error(error):
                raise
            raise _wrong_type(type(self).__name__, name, value, getattr(self, name)) from None

    def __init__(self, *args, **attributes):
        try:
            original_init(self, *args, **attributes)
        except TypeError as error:
            if not _boost_type_error(error):
                raise
            defaults = cls()
            for name, value in attributes.items():
                if hasattr(defaults, name) and not _fits(value, getattr(defaults, name)):
                    raise _wrong_type(cls.__name__, name, value, getattr(defaults, name)) from None
            raise

    cls.__setattr__, cls.__init__ = __setattr__, __init__
    cls._viscbridge_typed = True


def install():
    """Wrap every ViscBridge class registered in yade.wrapper (once)."""
    import yade.wrapper as yw
    for name in dir(yw):
        cls = getattr(yw, name)
        if 'ViscBridge' in name and isinstance(cls, type) and not cls.__dict__.get('_viscbridge_typed'):
            _wrap(cls)
