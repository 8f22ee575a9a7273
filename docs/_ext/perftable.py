"""Numbers that stay true: the manual's measured numbers are read from the benchmarks' CSV files
(docs/perf/*.csv, written by bench/*.py) when the manual is built, never typed by hand.

Two ways in, for a page in Markdown (MyST):

A table, by the ``perf-table`` directive: the CSV's path (relative to the page; a bare file name
is looked up in ``perf/`` beside it), options, then one line per column:
``EXPRESSION | HEADER | FORMAT`` (header and format optional)::

    ```{perf-table} perf/settling_cost_1threads.csv
    :where: run=viscbridge implicit
    viscosity | μ [Pa·s] | %g
    wall_seconds | wall time [s] | %.1f
    wall_seconds / steps * 1e3 | ms per step | %.2f
    ```

One number in running text, by the ``perf`` role: ``FILE|WHERE|EXPRESSION|FORMAT|BASE`` (format
and base optional), whose WHERE must select exactly one row::

    {perf}`settling_cost_1threads.csv|viscosity=100,run=viscbridge implicit|ratio_to_yade|%.2f`

(The ``|`` would split a Markdown table's cell: in tables, use the directive.)

Ratios between rows: a table's ``:base:`` (a WHERE) and ``:match:`` (columns) give every row the one
row that BASE selects among those with the same values in the MATCH columns, and ``base.COLUMN`` in
an expression reads it; for the role, BASE is a WHERE that selects one row::

    ```{perf-table} perf/peer_liggghts.csv
    :where: run=viscbridge implicit
    :base: run=liggghts
    :match: spheres, viscosity
    base.wall_seconds / wall_seconds | LIGGGHTS ÷ ViscBridge | %.0f
    ```

WHERE: conditions joined by ``,``, each ``column OP value`` with OP one of ``= != < <= > >=``;
values compare as numbers when both sides are numbers (``viscosity=100`` matches ``100.0``), as
text otherwise; ``column=a;b`` matches either; ``column=`` an empty cell.  Empty: every row.

EXPRESSION: a column name, or arithmetic (``+ - * / **``, parentheses, numbers, ``min``, ``max``,
``abs``) over column names and ``base.COLUMN`` — a derived column, e.g. ``explicit_critical_seconds / cheapest_seconds``.

FORMAT: a printf format (``%.2f``, ``%.3g``, ``%d``, ``%s``; literal text around it is kept:
``%.1f s``), or ``int`` (rounded, thousands apart: 85 320), ``sig2`` / ``sig3`` … (n significant digits,
no exponent: 4 270, 5.56), or ``sci`` / ``sci2`` / ``sci3``
(n significant digits as a·10ⁿ), or ``map:A=text;B=other`` (a cell's value A printed as `text`:
``map:True=projected;False=``).  Exponents print as ·10ⁿ, in text cells too.  Default: ``%.3g`` for numbers, the cell's
text otherwise; an empty or NaN cell prints as ``–``.

The same functions serve without Sphinx (tests/unit, and the README's test, which GitHub renders
without Sphinx): :func:`load`, :func:`select`, :func:`value`, :func:`table`, :func:`references`.
Every error names the file, and the column, the condition or the rows it concerns
(:class:`PerfError`).
"""
import ast
import csv
import math
import operator
import os
import re

__all__ = ['PerfError', 'DOCS', 'resolve', 'load', 'parse_where', 'select', 'evaluate', 'format_value', 'value', 'table',
           'parse_role', 'parse_columns', 'references', 'check_reference', 'setup']

#: The manual's source directory (docs/): paths are relative to it unless a page's own is given.
DOCS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EMPTY = '–'


class PerfError(LookupError):
    """A CSV, a column, a condition or a row that a reference needs and does not find."""


# ------------------------------------------------------------------------------------------------
# CSV files
# ------------------------------------------------------------------------------------------------

def resolve(path, docs=None):
    """The absolute path of `path`: relative to the directory `docs` (default: docs/); a bare file
    name not found there is looked up in docs/perf/."""
    base = DOCS if docs is None else docs
    candidates = [path] if os.path.isabs(path) else [os.path.join(base, path)]
    if not os.path.isabs(path) and os.path.dirname(path) == '':
        candidates.append(os.path.join(base, 'perf', path))
    for c in candidates:
        if os.path.isfile(c):
            return os.path.normpath(c)
    raise PerfError('perf: no CSV file %r (looked for %s)' % (path, ', '.join(os.path.normpath(c) for c in candidates)))


_cache = {}


def load(path, docs=None):
    """The rows of a CSV file as dicts of strings (header → cell), in file order; cached until the
    file changes."""
    full = resolve(path, docs)
    stamp = os.stat(full).st_mtime_ns
    hit = _cache.get(full)
    if hit and hit[0] == stamp:
        return hit[1]
    with open(full, newline='') as fh:
        reader = csv.DictReader(fh)
        rows = [dict(r) for r in reader]
        columns = list(reader.fieldnames or [])
    rows = _Rows(rows, columns, os.path.relpath(full, DOCS) if full.startswith(DOCS) else full)
    _cache[full] = (stamp, rows)
    return rows


class _Rows(list):
    """A CSV's rows, knowing their file's name and columns (for the error messages)."""

    def __init__(self, rows, columns, name):
        super().__init__(rows)
        self.columns, self.name = columns, name


def _number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


# ------------------------------------------------------------------------------------------------
# Selecting rows
# ------------------------------------------------------------------------------------------------

_OPS = (('<=', operator.le), ('>=', operator.ge), ('!=', operator.ne), ('=', operator.eq), ('<', operator.lt),
        ('>', operator.gt))


def parse_where(where):
    """``'a=1,b!=x'`` → [('a', '=', ['1']), ('b', '!=', ['x'])]; a list of such tuples passes through."""
    if where is None:
        return []
    if not isinstance(where, str):
        return list(where)
    conditions = []
    for part in where.split(','):
        part = part.strip()
        if not part:
            continue
        for symbol, _ in _OPS:
            column, sep, rest = part.partition(symbol)
            if sep and column.strip():
                conditions.append((column.strip(), symbol, [v.strip() for v in rest.split(';')]))
                break
        else:
            raise PerfError('perf: condition %r is not COLUMN=VALUE (or != < <= > >=)' % part)
    return conditions


def _matches(cell, symbol, wanted):
    op = dict(_OPS)[symbol]
    a = _number(cell)
    hits = []
    for w in wanted:
        b = _number(w)
        if a is not None and b is not None:
            hits.append(op(a, b))
        elif symbol in ('=', '!='):
            hits.append(op(cell.strip(), w))
        else:
            hits.append(False)
    return all(hits) if symbol == '!=' else any(hits)


def select(rows, where):
    """The rows that meet every condition of `where` (see :func:`parse_where`); a condition on a
    column the file does not have is an error naming it."""
    conditions = parse_where(where)
    columns = getattr(rows, 'columns', None) or (list(rows[0]) if rows else [])
    name = getattr(rows, 'name', 'the rows')
    for column, _, _ in conditions:
        if column not in columns:
            raise PerfError('perf: %s has no column %r (columns: %s)' % (name, column, ', '.join(columns)))
    return [r for r in rows if all(_matches(r[c] or '', s, w) for c, s, w in conditions)]


# ------------------------------------------------------------------------------------------------
# Cells and derived columns
# ------------------------------------------------------------------------------------------------

_ARITH = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
          ast.Pow: operator.pow}
_FUNCS = {'min': min, 'max': max, 'abs': abs}


def evaluate(row, expression, name='the row', base=None):
    """The value of `expression` in `row`: a column's cell as it is (text), or arithmetic over
    columns as a float (an empty cell makes it NaN); ``base.COLUMN`` is a cell of the row `base`
    (the reference row of a ratio, see :func:`table`)."""
    expression = expression.strip()
    if expression in row:
        return row[expression]

    def cell(source, column, label):
        if column not in source:
            raise PerfError('perf: %s has no column %r (columns: %s)' % (name, column, ', '.join(source)))
        x = _number(source[column])
        if x is None:
            if (source[column] or '').strip() == '':
                return math.nan
            raise PerfError('perf: %s, %scolumn %r: %r is not a number' % (name, label, column, source[column]))
        return x
    try:
        tree = ast.parse(expression, mode='eval')
    except SyntaxError:
        raise PerfError('perf: %s has no column %r (columns: %s)' % (name, expression, ', '.join(row)))

    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return float(node.value)
        if isinstance(node, ast.Name):
            return cell(row, node.id, '')
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == 'base':
            if base is None:
                raise PerfError('perf: %r uses base.%s, but no base row is given (:base:)' % (expression, node.attr))
            return cell(base, node.attr, 'base row, ')
        if isinstance(node, ast.BinOp) and type(node.op) in _ARITH:
            a, b = ev(node.left), ev(node.right)
            try:
                return _ARITH[type(node.op)](a, b)
            except ZeroDivisionError:
                return math.nan
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            return -ev(node.operand) if isinstance(node.op, ast.USub) else ev(node.operand)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCS and not node.keywords:
            return float(_FUNCS[node.func.id](*[ev(a) for a in node.args]))
        raise PerfError('perf: %r: only column names, base.COLUMN, numbers, + - * / **, min, max and abs are allowed'
                        % expression)

    return ev(tree)


_SUPERSCRIPT = str.maketrans('-0123456789', '⁻⁰¹²³⁴⁵⁶⁷⁸⁹')


def _pretty_exponents(text):
    """'1.17e-08' → '1.17·10⁻⁸' (in any text a printf format made)."""
    def sub(m):
        exponent = str(int(m.group(2))).translate(_SUPERSCRIPT)
        return '%s·10%s' % (m.group(1), exponent)
    return re.sub(r'(\d(?:\.\d+)?)e([+-]?\d+)', sub, text)


def format_value(x, fmt=None):
    """`x` (a cell's text or a number) printed with `fmt` (see the module's documentation)."""
    if fmt is not None and fmt.startswith('map:'):
        table = dict(pair.partition('=')[::2] for pair in fmt[4:].split(';'))
        key = x if isinstance(x, str) else format_value(x)
        if key.strip() not in table:
            raise PerfError('perf: %r is not one of the values of format %r' % (key, fmt))
        return table[key.strip()]
    if isinstance(x, str):
        if x.strip() == '':
            return EMPTY
        number = _number(x)
        if number is None or fmt in ('%s', 'text'):
            if fmt not in (None, '%s', 'text'):
                raise PerfError('perf: %r is not a number, format %r' % (x, fmt))
            return _pretty_exponents(x)
        x = number
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return EMPTY
    if fmt is None:
        fmt = '%.3g'
    if fmt == 'int':
        return '{:,d}'.format(int(round(x))).replace(',', '\u202f')
    m = re.fullmatch(r'sig(\d)', fmt)
    if m:  # n significant digits, no exponent, thousands apart: 4266.4 → 4 270, 5.561 → 5.56
        digits = int(m.group(1))
        if x == 0 or math.isinf(x):
            return '%g' % x
        decimals = max(0, digits - 1 - int(math.floor(math.log10(abs(x)))))
        rounded = round(x, digits - 1 - int(math.floor(math.log10(abs(x)))))
        return '{:,.{}f}'.format(rounded, decimals).replace(',', '\u202f')
    m = re.fullmatch(r'sci(\d?)', fmt)
    if m:
        digits = int(m.group(1) or 3)
        if x == 0:
            return '0'
        exponent = int(math.floor(math.log10(abs(x))))
        mantissa = round(x / 10 ** exponent, digits - 1)
        if abs(mantissa) >= 10:
            mantissa, exponent = mantissa / 10, exponent + 1
        text = ('%.*f' % (digits - 1, mantissa)).rstrip('0').rstrip('.') if digits > 1 else '%d' % mantissa
        if exponent == 0:
            return text
        power = '10' + str(exponent).translate(_SUPERSCRIPT)
        return power if text == '1' else '%s·%s' % (text, power)
    if fmt == '%s':
        return _pretty_exponents('%s' % x)
    if '%' not in fmt:
        raise PerfError('perf: format %r is not a printf format (%%.2f), int or sci' % fmt)
    try:
        return _pretty_exponents(fmt % (int(round(x)) if re.search(r'%[-+ 0#]*\d*d', fmt) else x))
    except (TypeError, ValueError) as e:
        raise PerfError('perf: format %r: %s' % (fmt, e))


# ------------------------------------------------------------------------------------------------
# The two ways in: one value, a table
# ------------------------------------------------------------------------------------------------

def _one(rows, where):
    chosen = select(rows, where)
    if len(chosen) != 1:
        raise PerfError('perf: %s: %r selects %d rows, not one%s' % (
            rows.name, where, len(chosen), '' if not chosen else ' (add a condition)'))
    return chosen[0]


def value(path, where, column, fmt=None, docs=None, base=None):
    """One number in running text: `column` (a column or an expression) of the single row of
    `path` that `where` selects, formatted (:func:`format_value`); `base`, a second WHERE selecting
    one row, is the row ``base.COLUMN`` reads.  The README's test uses it too:
    ``value('settling_cost_1threads.csv', 'viscosity=100,run=viscbridge implicit', 'ratio_to_yade', '%.2f')``."""
    rows = load(path, docs)
    reference = _one(rows, base) if base else None
    return format_value(evaluate(_one(rows, where), column, rows.name, reference), fmt)


def table(path, columns, where=None, docs=None, base=None, match=()):
    """A table of `path`'s rows that `where` selects: (headers, rows of formatted cells), with
    `columns` a list of (expression, header, format) (or the lines of :func:`parse_columns`).
    `base` (a WHERE) and `match` (columns) give each row a reference row, the one row that `base`
    selects among those equal to it in every `match` column, which ``base.COLUMN`` reads: e.g.
    base ``run=liggghts``, match ``spheres, viscosity``, column ``base.wall_seconds / wall_seconds``."""
    rows = load(path, docs)
    match = [m.strip() for m in match.split(',')] if isinstance(match, str) else list(match)
    match = [m for m in match if m]
    columns = parse_columns(columns) if isinstance(columns, str) else [parse_column(c) if isinstance(c, str) else c for c in columns]
    if not columns:
        raise PerfError('perf: %s: a table needs at least one column' % rows.name)
    chosen = select(rows, where)
    if not chosen:
        raise PerfError('perf: %s: %r selects no row' % (rows.name, where))
    references = select(rows, base) if base else None
    body = []
    for r in chosen:
        reference = None
        if references is not None:
            same = [b for b in references if all(_matches(b[m] or '', '=', [r[m] or '']) for m in match)]
            if len(same) != 1:
                raise PerfError('perf: %s: base %r%s selects %d rows for the row %s, not one' % (
                    rows.name, base, ' with the same ' + ', '.join(match) if match else '', len(same),
                    ', '.join('%s=%s' % (m, r[m]) for m in match) or str(r)))
            reference = same[0]
        body.append([format_value(evaluate(r, e, rows.name, reference), f) for e, _, f in columns])
    return [h for _, h, _ in columns], body


def parse_column(line):
    """``'wall_seconds | wall time [s] | %.1f'`` → ('wall_seconds', 'wall time [s]', '%.1f')."""
    parts = [p.strip() for p in line.split('|')]
    if not parts[0] or len(parts) > 3:
        raise PerfError('perf: column line %r is not EXPRESSION | HEADER | FORMAT' % line)
    expression = parts[0]
    header = parts[1] if len(parts) > 1 and parts[1] else expression
    fmt = parts[2] if len(parts) > 2 and parts[2] else None
    return expression, header, fmt


def parse_columns(text):
    """The column lines of a directive (blank lines and lines starting with # skipped)."""
    lines = text.splitlines() if isinstance(text, str) else list(text)
    return [parse_column(l) for l in lines if l.strip() and not l.strip().startswith('#')]


def parse_role(text):
    """``'FILE|WHERE|EXPRESSION|FORMAT|BASE'`` (format and base optional) → (file, where,
    expression, format, base)."""
    parts = [p.strip() for p in text.split('|')]
    if len(parts) not in (3, 4, 5) or not parts[0] or not parts[2]:
        raise PerfError('perf: %r is not FILE|WHERE|COLUMN|FORMAT (|BASE)' % text)
    parts += [''] * (5 - len(parts))
    return parts[0], parts[1], parts[2], parts[3] or None, parts[4] or None


# ------------------------------------------------------------------------------------------------
# References in Markdown pages (for the test that keeps them pointing at real rows and columns)
# ------------------------------------------------------------------------------------------------

_FENCE = re.compile(r'^(\s*)(`{3,}|~{3,})\s*(\{perf-table\})?\s*(.*)$')
_ROLE = re.compile(r'\{perf\}`([^`]+)`')


def references(markdown):
    """Every perf reference of a Markdown text: ('table', line, path, options, column lines) and
    ('value', line, role text); roles inside other fenced blocks are not references."""
    found, fence, lines = [], None, markdown.splitlines()
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if fence is None and m:
            marker, directive, argument = m.group(2), m.group(3), m.group(4).strip()
            body, j = [], i + 1
            while j < len(lines) and not lines[j].strip().startswith(marker):
                body.append(lines[j])
                j += 1
            if directive:
                options = {}
                content = []
                for b in body:
                    o = re.match(r'^\s*:([\w-]+):\s*(.*)$', b)
                    if o and not content:
                        options[o.group(1)] = o.group(2).strip()
                    else:
                        content.append(b)
                found.append(('table', i + 1, argument, options, content))
            i = j + 1
            continue
        for r in _ROLE.finditer(lines[i]):
            found.append(('value', i + 1, r.group(1)))
        i += 1
    return found


def check_reference(reference, docs=None):
    """Raise PerfError if a reference (from :func:`references`) does not resolve; else return what
    it renders (the table's (headers, rows), or the value's text)."""
    if reference[0] == 'table':
        _, _, path, options, content = reference
        return table(path, parse_columns(content), options.get('where'), docs, options.get('base'), options.get('match', ''))
    path, where, column, fmt, base = parse_role(reference[2])
    return value(path, where, column, fmt, docs, base)


# ------------------------------------------------------------------------------------------------
# Sphinx
# ------------------------------------------------------------------------------------------------

def _directive():
    from docutils import nodes
    from docutils.parsers.rst import Directive, directives

    class PerfTable(Directive):
        """``perf-table``: a CSV of docs/perf rendered as a table when the manual is built."""
        required_arguments = 1
        has_content = True
        option_spec = {'where': directives.unchanged, 'base': directives.unchanged, 'match': directives.unchanged,
                       'class': directives.class_option}

        def run(self):
            env = self.state.document.settings.env
            here = os.path.dirname(env.doc2path(env.docname))
            try:
                full = resolve(self.arguments[0], here)
                env.note_dependency(full)
                headers, body = table(full, parse_columns(self.content), self.options.get('where'), here,
                                      self.options.get('base'), self.options.get('match', ''))
            except PerfError as e:
                raise self.error('%s (in %s)' % (e, env.docname))
            tab = nodes.table(classes=['perf-table'] + self.options.get('class', []))
            group = nodes.tgroup(cols=len(headers))
            tab += group
            for _ in headers:
                group += nodes.colspec(colwidth=1)
            head, rows = nodes.thead(), nodes.tbody()
            group += head
            group += rows
            for cells, parent in [(headers, head)] + [(r, rows) for r in body]:
                row = nodes.row()
                for c in cells:
                    row += nodes.entry('', nodes.paragraph(text=c))
                parent += row
            return [tab]

    return PerfTable


def perf_role(name, rawtext, text, lineno, inliner, options=None, content=None):
    """``perf``: one number of a CSV of docs/perf, in running text."""
    from docutils import nodes
    env = inliner.document.settings.env
    here = os.path.dirname(env.doc2path(env.docname))
    try:
        path, where, column, fmt, reference = parse_role(text)
        env.note_dependency(resolve(path, here))
        return [nodes.Text(value(path, where, column, fmt, here, reference))], []
    except PerfError as e:
        message = inliner.reporter.error('%s (in %s)' % (e, env.docname), line=lineno)
        problem = inliner.problematic(rawtext, rawtext, message)
        return [problem], [message]


def setup(app):
    app.add_directive('perf-table', _directive())
    app.add_role('perf', perf_role)
    return {'version': '1', 'parallel_read_safe': True, 'parallel_write_safe': True}
