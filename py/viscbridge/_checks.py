"""Argument checks shared by the Python tools (plain Python, no YADE needed).

Every failure is a ValueError that names the function, the parameter, the value given and what is
allowed, the way the C++ classes report a bad attribute.
"""
import math
import numbers
import sys
import warnings

__all__ = ['reject', 'number', 'positive', 'non_negative', 'in_range', 'integer', 'boolean', 'choice', 'implausible']


def implausible(key, message):
    """A value no wet granulation run uses (a likely unit mistake): a warning in YADE's log, once per
    scene and `key` (ViscBridgeContext.warnOnce); the caller goes on.  Outside YADE a Python warning."""
    wrapper = sys.modules.get('yade.wrapper')
    context = getattr(wrapper, 'ViscBridgeContext', None)
    if context is not None:
        context.warnOnce(key, message)
    else:
        warnings.warn(message, stacklevel=3)


def suggestion(name, known):
    """'; did you mean 'x'?' for the name of `known` closest to `name` (a typo), or ''."""
    import difflib
    close = difflib.get_close_matches(name, known, n=1)
    return "; did you mean %r?" % close[0] if close else ''


def reject(func, name, value, allowed):
    raise ValueError('%s: %s=%r is out of range; allowed: %s.' % (func, name, value, allowed))


def number(func, name, value, allowed):
    """A finite real number (int, float, numpy scalar) as float; str and bool are refused."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        reject(func, name, value, allowed)
    x = float(value)
    if not math.isfinite(x):
        reject(func, name, value, allowed)
    return x


def positive(func, name, value, unit=''):
    allowed = '> 0 (finite)' + unit
    x = number(func, name, value, allowed)
    if not x > 0:
        reject(func, name, value, allowed)
    return x


def non_negative(func, name, value, unit=''):
    allowed = '>= 0 (finite)' + unit
    x = number(func, name, value, allowed)
    if not x >= 0:
        reject(func, name, value, allowed)
    return x


def in_range(func, name, value, lo, hi, lo_open=False, hi_open=False, unit=''):
    """lo ≤ value ≤ hi, with open ends where asked (the message shows the interval)."""
    allowed = '%s%g, %g%s%s' % ('(' if lo_open else '[', lo, hi, ')' if hi_open else ']', unit)
    x = number(func, name, value, allowed)
    if not ((x > lo if lo_open else x >= lo) and (x < hi if hi_open else x <= hi)):
        reject(func, name, value, allowed)
    return x


def integer(func, name, value, minimum=None):
    """An integer (int or an integral float such as 300.0), at least `minimum`."""
    allowed = 'an integer' + ('' if minimum is None else ' >= %d' % minimum)
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        reject(func, name, value, allowed)
    if not math.isfinite(value) or int(value) != value or (minimum is not None and value < minimum):
        reject(func, name, value, allowed)
    return int(value)


def boolean(func, name, value):
    if not isinstance(value, bool):
        reject(func, name, value, 'True or False')
    return value


def choice(func, name, value, choices):
    if not isinstance(value, str) or value not in choices:
        raise ValueError('%s: %s=%r is not a known name; allowed: %s.' % (
            func, name, value, ', '.join(repr(c) for c in choices)))
    return value
