#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""No function outside src/kernels/, tests/ and generated code is longer than
100 lines, counted from the line of its opening brace to the line of its
closing one (both included).

usage: check_function_length.py SOURCE_ROOT [FILE...]
  With only SOURCE_ROOT, scans every C and C++ source and header under it except
  src/kernels/, tests/, hidden directories and build directories (the
  generated code lives there).  With FILEs, scans those files only.
  Prints one line per long function, "path:line: name is N lines (limit 100)",
  and exits 1 if there is one.

The scanner reads C and C++ as tokens: comments, string and character literals
(raw strings included) and preprocessor lines cannot open or close a brace.
Of a conditional (#if/#ifdef ... #endif) whose branches do not each balance
their braces, only the first branch is read, as a compiler would see one of
them; #if 0 branches are not read.  A function is a brace block at file,
namespace, extern "C" or class level whose head ends with a parameter list
(and qualifiers, a trailing return type or a constructor's initialisers); its
name is the identifier before that list.
"""
import os
import re
import sys

LIMIT = 100
SOURCES = ('.c', '.cc', '.cpp', '.cxx', '.h', '.hh', '.hpp')
EXCLUDED = ('src/kernels', 'tests')

TOKEN = re.compile(r'''
    (?P<nl>\n)
  | (?P<ws>[ \t\r\f\v]+|\\\n)
  | (?P<lc>//[^\n]*)
  | (?P<bc>/\*.*?\*/)
  | (?P<raw>(?:u8|[uUL])?R"(?P<delim>[^()\\ \t\n]{0,16})\(.*?\)(?P=delim)")
  | (?P<str>(?:u8|[uUL])?"(?:[^"\\\n]|\\.)*")
  | (?P<chr>(?:u8|[uUL])?'(?:[^'\\\n]|\\.)*')
  | (?P<num>\.?[0-9](?:[eEpP][+-]|'[0-9A-Za-z_]|[0-9A-Za-z_.])*)
  | (?P<id>[A-Za-z_][A-Za-z_0-9]*)
  | (?P<op>::|->|&&|\|\||[<>=!+\-*/%&|^]=|.)
''', re.S | re.X)


def tokens(text):
    """(kind, value, line) for every token, preprocessor lines as ('pp',
    directive, line), newlines dropped."""
    out = []
    line = 1
    pos = 0
    at_line_start = True
    n = len(text)
    while pos < n:
        m = TOKEN.match(text, pos)
        kind = 'raw' if m.group('raw') else m.lastgroup
        value = m.group(0)
        if kind == 'nl':
            at_line_start = True
        elif kind in ('ws', 'lc', 'bc'):
            pass
        elif value == '#' and at_line_start:
            # a directive runs to the end of the line, continuations included;
            # comments inside it may span lines
            end = pos + 1
            while end < n and text[end] != '\n':
                c = text[end]
                if c == '\\' and end + 1 < n and text[end + 1] == '\n':
                    end += 2
                    continue
                if text.startswith('/*', end):
                    close = text.find('*/', end + 2)
                    end = n if close < 0 else close + 2
                    continue
                if text.startswith('//', end):
                    while end < n and text[end] != '\n':
                        end += 1
                    break
                end += 1
            directive = text[pos + 1:end]
            word = re.match(r'\s*(\w*)\s*(.*)', directive, re.S)
            out.append(('pp', (word.group(1), word.group(2).strip()), line))
            line += text.count('\n', pos, end)
            pos = end
            continue
        else:
            at_line_start = False
            out.append((kind if kind in ('id', 'num', 'op') else 'lit', value, line))
        line += value.count('\n')
        pos = m.end()
    return out


def is_zero(condition):
    """Is this #if or #elif condition a literal 0?"""
    return re.sub(r'/\*.*?\*/|//.*', '', condition, flags=re.S).strip() == '0'


def resolve_conditionals(toks):
    """Drops the preprocessor lines; of each conditional keeps every branch
    if each balances its braces, else the first branch only; drops #if 0."""
    def parse(i, top):
        # returns (list of items, index after); an item is a token or
        # ('cond', [(is_zero, items), ...])
        items = []
        while i < len(toks):
            t = toks[i]
            if t[0] == 'pp':
                word, rest = t[1]
                if word in ('if', 'ifdef', 'ifndef'):
                    branches = []
                    zero = word == 'if' and is_zero(rest)
                    i += 1
                    while True:
                        body, i = parse(i, False)
                        branches.append((zero, body))
                        if i >= len(toks):
                            break
                        w, r = toks[i][1]
                        i += 1
                        if w == 'endif':
                            break
                        zero = w == 'elif' and is_zero(r)
                    items.append(('cond', branches))
                    continue
                if word in ('elif', 'else', 'endif') and not top:
                    return items, i
                i += 1
                continue
            items.append(t)
            i += 1
        return items, i

    def delta(items):
        d = 0
        for it in flatten(items):
            if it[1] == '{':
                d += 1
            elif it[1] == '}':
                d -= 1
        return d

    def flatten(items):
        out = []
        for it in items:
            if it[0] == 'cond':
                live = [b for z, b in it[1] if not z]
                if live and all(delta(b) == 0 for b in live):
                    for b in live:
                        out.extend(flatten(b))
                elif live:
                    out.extend(flatten(live[0]))
            else:
                out.append(it)
        return out

    items, _ = parse(0, True)
    return flatten(items)


def skip_block(toks, i):
    """toks[i] is '{': index of its matching '}'."""
    depth = 0
    while i < len(toks):
        v = toks[i][1]
        if toks[i][0] == 'op':
            if v == '{':
                depth += 1
            elif v == '}':
                depth -= 1
                if depth == 0:
                    return i
        i += 1
    return len(toks) - 1


def top_level(head):
    """The head's tokens outside parentheses and brackets, each outermost
    group collapsed to one ('group', '(' or '[', index) item."""
    out = []
    depth = 0
    for k, (kind, v, line) in enumerate(head):
        if kind == 'op' and v in '([':
            if depth == 0:
                out.append(('group', v, k))
            depth += 1
        elif kind == 'op' and v in ')]':
            depth -= 1
        elif depth == 0:
            out.append((kind, v, k))
    return out


QUALIFIERS = {'const', 'volatile', 'override', 'final', 'noexcept', 'throw',
              'mutable', '&', '&&', '__attribute__', 'try'}


def function_name(head):
    """The function's name if a block with this head is a function body."""
    tl = top_level(head)
    if not tl:
        return None
    for j, (kind, v, _) in enumerate(tl):
        if kind == 'op' and v == '=' and not (j and tl[j - 1][1] == 'operator'):
            return None  # an initialiser
    # the parameter list: the first paren group at top level that is preceded
    # by a name (after it only qualifiers, attributes, a trailing return type
    # or a constructor's initialisers)
    for j, (kind, v, k) in enumerate(tl):
        if kind != 'group' or v != '(' or j == 0:
            continue
        prev = tl[j - 1]
        if prev[0] == 'id' and prev[1] not in ('operator', '__attribute__', 'alignas',
                                                 'decltype', 'sizeof',
                                                 '__declspec', 'throw', 'noexcept'):
            name = prev[1]
            start = j - 1
        elif prev[0] == 'op' and j >= 2 and tl[j - 2][1] == 'operator':
            name = 'operator' + prev[1]
            start = j - 2
        elif prev[0] == 'group' and prev[1] == '(' and j >= 2 and tl[j - 2][1] == 'operator':
            name = 'operator()'
            start = j - 2
        else:
            continue
        # qualified names: A::B::name, A::~A
        if start >= 1 and tl[start - 1][1] == '~':
            name = '~' + name
            start -= 1
        while start >= 2 and tl[start - 1][1] == '::' and tl[start - 2][0] == 'id':
            name = tl[start - 2][1] + '::' + name
            start -= 2
        rest = tl[j + 1:]
        if function_tail_ok(rest):
            return name
    return None


def function_tail_ok(rest):
    """What may follow a parameter list before the body."""
    k = 0
    while k < len(rest):
        kind, v, _ = rest[k]
        if kind == 'group':
            k += 1  # __attribute__((...)), noexcept(...), throw()
            continue
        if v in QUALIFIERS or (kind == 'id' and v.isupper()):
            k += 1  # qualifiers and attribute macros (G_GNUC_UNUSED ...)
            continue
        if v == '->':
            return True  # trailing return type runs to the brace
        if v == ':':
            return True  # constructor initialisers
        return False
    return True


def functions(toks):
    """(name, first line, last line) of every function body."""
    found = []
    head = []
    i = 0
    while i < len(toks):
        kind, v, line = toks[i]
        if kind == 'op' and v == '{':
            name = function_name(head)
            tl = top_level(head)
            if name is not None and any(t[1] == ':' for t in tl) and \
                    (head[-1][0] == 'id' or head[-1][1] == '>'):
                # a member's brace initialiser in a constructor's list: part
                # of the head
                end = skip_block(toks, i)
                head.extend(toks[i:end + 1])
                i = end + 1
                continue
            if name is not None:
                end = skip_block(toks, i)
                found.append((name, line, toks[end][2]))
                head = []
                i = end + 1
                continue
            words = [t[1] for t in tl if t[0] in ('id', 'lit')]
            if words and (words[0] == 'namespace' or
                          (words[0] == 'extern' and len(words) > 1 and words[1].startswith('"')) or
                          any(w in ('class', 'struct', 'union') for w in words)) \
                    and not any(t[1] == '=' for t in tl):
                head = []  # a namespace, extern "C" or class body: read into it
                i += 1
                continue
            # an initialiser, an enum, a compound literal: not a function
            end = skip_block(toks, i)
            head.extend(toks[i:end + 1])
            i = end + 1
            continue
        if kind == 'op' and v in ('}', ';'):
            head = []
        elif kind == 'op' and v == ':' and len(head) == 1 and head[0][1] in (
                'public', 'private', 'protected'):
            head = []
        else:
            head.append(toks[i])
        i += 1
    return found


def scan(path):
    with open(path, encoding='utf-8', errors='replace') as f:
        text = f.read()
    toks = resolve_conditionals(tokens(text))
    return [(name, first, last, last - first + 1)
            for name, first, last in functions(toks)]


def sources(root):
    for dirpath, dirnames, filenames in os.walk(root):
        rel = os.path.relpath(dirpath, root)
        rel = '' if rel == '.' else rel.replace(os.sep, '/')
        keep = []
        for d in sorted(dirnames):
            sub = (rel + '/' + d).lstrip('/')
            full = os.path.join(dirpath, d)
            if d.startswith('.') or sub in EXCLUDED or \
                    os.path.exists(os.path.join(full, 'meson-private')) or \
                    os.path.exists(os.path.join(full, 'build.ninja')):
                continue
            keep.append(d)
        dirnames[:] = keep
        for name in sorted(filenames):
            if name.endswith(SOURCES):
                yield os.path.join(dirpath, name)


def main(argv):
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    root = argv[1]
    paths = argv[2:] or list(sources(root))
    if not paths:
        print('check_function_length: no sources under %s' % root, file=sys.stderr)
        return 2
    status = 0
    count = 0
    for path in paths:
        for name, first, _last, length in scan(path):
            count += 1
            if length > LIMIT:
                print('%s:%d: %s is %d lines (limit %d)'
                      % (os.path.relpath(path, root), first, name, length, LIMIT))
                status = 1
    if count == 0:
        print('check_function_length: no functions found', file=sys.stderr)
        return 2
    if status == 0:
        print('check_function_length: %d functions in %d files, none over %d lines'
              % (count, len(paths), LIMIT))
    return status


if __name__ == '__main__':
    sys.exit(main(sys.argv))
