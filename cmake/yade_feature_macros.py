#!/usr/bin/env python3
"""Derive the compile definitions of an installed YADE from its own build script.

A YADE plugin must be compiled with the same feature macros as YADE itself (several of them change
the layout of Scene, Body and Shape).  YADE records its enabled features in ``yade.config.features``;
the macro each feature turns on is defined by YADE's top-level CMakeLists.txt, in the IF-branch
that appends the feature to CONFIGURED_FEATS.  This script reads that file (of the same release as
the installed binary) and prints, one per line, the definitions the plugin needs:

  * for every enabled feature, the ``-D`` tokens of the branch that enables it;
  * for every YADE feature that is *not* enabled, the ``-D`` tokens of the other branches of the IF
    that would enable it (e.g. the Eigen no-vectorisation macros that go with a missing VECTORIZE);
  * the definitions YADE adds unconditionally or from its precision settings
    (YADE_REAL_BIT/DEC, MAX_LOG_LEVEL, YADE_ODEINT, YADE_DISABLE_REAL_MULTI_HP), from yade.config.

An enabled feature that the build script does not know is an error: a newer YADE needs a look.

usage: yade_feature_macros.py YADE_CMAKELISTS CONFIG_PY
"""
import re
import runpy
import sys


class Branch:
    def __init__(self, condition, block):
        self.condition, self.block = condition, block  # block: the branches of one IF, in order
        self.enabled, self.defs = [], []
        block.append(self)


def strip_comment(line):
    out, quoted = [], False
    for ch in line:
        if ch == '"':
            quoted = not quoted
        if ch == '#' and not quoted:
            break
        out.append(ch)
    return ''.join(out)


def parse_branches(text):
    """Every IF/ELSEIF/ELSE branch (plus the top level) with what it does directly."""
    top = Branch('<top level>', [])
    branches, stack = [top], [top.block]  # stack of IF blocks, each a list of its branches
    for raw in text.splitlines():
        line = strip_comment(raw).strip()
        m = re.match(r'(?i)(if|elseif|else|endif)\s*\((.*)\)?', line)
        key = m.group(1).lower() if m else None
        if key == 'if':
            stack.append([]); branches.append(Branch(m.group(2), stack[-1])); continue
        if key in ('elseif', 'else'):
            branches.append(Branch(key + ' ' + m.group(2), stack[-1])); continue
        if key == 'endif':
            stack.pop(); continue
        cur = stack[-1][-1]
        feats = re.match(r'(?i)set\s*\(\s*CONFIGURED_FEATS\s+"\$\{\w+\}\s*([^"]*)"', line)
        if feats:
            cur.enabled.extend(feats.group(1).split())
            continue
        if re.match(r'(?i)(add_definitions|set\s*\(\s*CMAKE_CXX_FLAGS\b)', line):
            cur.defs.extend(re.findall(r'-D[A-Za-z_]\w*(?:=[^\s")]+)?', line))
    return top, branches


def derive(cmakelists_text, config):
    features = [f for f in config['features'] if f]
    top, branches = parse_branches(cmakelists_text)
    known_enabled = {f: b for b in branches for f in b.enabled}
    unknown = [f for f in features if f not in known_enabled]
    if unknown:
        raise SystemExit('YADE features not found in its CMakeLists.txt: %s' % ' '.join(unknown))
    defs = []
    for f, b in known_enabled.items():
        if f in features:
            defs += b.defs
        else:
            # The other branches of the IF that would have enabled f: they say what a build
            # without f defines (e.g. EIGEN_DONT_VECTORIZE when VECTORIZE is absent).
            for sibling in b.block:
                if sibling is not b and not sibling.enabled:
                    defs += sibling.defs
    # Definitions outside any feature branch, with the values yade.config reports.
    values = {'MAX_LOG_LEVEL': None, 'REAL_PRECISION_BITS': config['highPrecisionBits'],
              'REAL_DECIMAL_PLACES': config['highPrecisionDecimalPlaces']}
    m = re.search(r'(?i)set\s*\(\s*MAX_LOG_LEVEL\s+"(\d+)"', cmakelists_text)
    values['MAX_LOG_LEVEL'] = m.group(1) if m else None
    for d in top.defs:
        defs.append(d)
    # YADE_ODEINT: Boost >= 1.53, true of every Boost YADE 2025 builds with.
    if '-DYADE_ODEINT' in cmakelists_text:
        defs.append('-DYADE_ODEINT')
    # RealHP<N> is compiled in exactly when YADE uses mpmath (REAL_MULTI_HP implies REAL_USE_MPMATH).
    if not config.get('highPrecisionMpmath', False):
        defs.append('-DYADE_DISABLE_REAL_MULTI_HP')
    resolved = []
    for d in defs:
        for var in re.findall(r'\$\{(\w+)\}', d):
            if values.get(var) is None:
                raise SystemExit('cannot resolve ${%s} in %s' % (var, d))
            d = d.replace('${%s}' % var, str(values[var]))
        if d not in resolved:
            resolved.append(d)
    return resolved


def main(argv):
    if len(argv) != 3:
        raise SystemExit(__doc__)
    with open(argv[1]) as fh:
        text = fh.read()
    config = runpy.run_path(argv[2])
    for d in derive(text, config):
        print(d[2:])  # without the -D: CMake's add_compile_definitions form


if __name__ == '__main__':
    main(sys.argv)
