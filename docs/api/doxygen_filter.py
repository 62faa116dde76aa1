#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Doxygen input filter for include/depthao/*.h: the headers keep the project's plain C
comments, and this turns them into documentation as Doxygen reads them, line for line
(line numbers stay the same):
  - the comment opening the file (after the SPDX line) describes the file (@file);
  - a comment that starts a line documents the declaration after it (/** ... */);
  - a comment after code (a member, a value, a macro) on the same line documents it
    (/**< ... */);
  - a comment after several names declared on one line (`double fx, fy;  /* px */`),
    or on the line before them, documents each of them (the line is split into one
    declaration per name);
  - the SPDX line and section rulers (/* --- ... */) stay plain comments."""
import os
import re
import sys

OPEN_LINE = re.compile(r'^(\s*)/\*(?![*!])')          # a comment starting a line
TRAILING = re.compile(r'^(\s*\S.*?[;,{]\s*|#\s*define\s+\w+\s+\S.*?)/\*(?![*!<])')  # code, then a comment
RULER = re.compile(r'^\s*/\*\s*-{3}')
NAME = r'\**\s*\w+(?:\[[^\]]*\])?'
MULTI = re.compile(r'^(\s*)((?:const\s+|unsigned\s+|struct\s+|enum\s+)*\w+\s+)(%s(?:\s*,\s*%s)+)\s*;(\s*)/\*(?![*!<])(.*)$'
                   % (NAME, NAME))


MULTI_BARE = re.compile(r'^(\s*)((?:const\s+|unsigned\s+|struct\s+|enum\s+)*\w+\s+)(%s(?:\s*,\s*%s)+)\s*;\s*$'
                        % (NAME, NAME))
ONE_LINE_DOC = re.compile(r'^\s*/\*\*\s(.*?)\s*\*/\s*$')


def split_bare(line, previous):
    """/** doc */ then int a, b;  ->  (blank) then int a; /**< doc */ int b; /**< doc */"""
    m, d = MULTI_BARE.match(line), ONE_LINE_DOC.match(previous or '')
    if not m or not d:
        return None
    indent, typ, names = m.groups()
    return indent + ' '.join('%s%s; /**< %s */' % (typ, n.strip(), d.group(1))
                             for n in names.split(','))


def split_names(line):
    """int a, b;  /* doc */  ->  int a; /**< doc */ int b; /**< doc */ (one line)."""
    m = MULTI.match(line)
    if not m:
        return None
    indent, typ, names, space, doc = m.groups()
    names = [n.strip() for n in names.split(',')]
    closed = '*/' in doc
    text = doc.split('*/')[0].strip() if closed else doc.strip() + ' ...'
    parts = ['%s%s; /**< %s */' % (typ, n, text) for n in names[:-1]]
    parts.append('%s%s;%s/**<%s' % (typ, names[-1], space or ' ', doc))
    return indent + ' '.join(parts)


def filter_text(text, name):
    out = []
    in_comment = False
    file_doc = False
    for line in text.split('\n'):
        if in_comment:
            out.append(line)
            if '*/' in line:
                in_comment = False
            continue
        if 'SPDX-License-Identifier' in line or RULER.match(line):
            pass
        elif OPEN_LINE.match(line):
            if not file_doc and not line.startswith((' ', '\t')):
                line = OPEN_LINE.sub(r'\1/** @file %s\n' % name, line, count=1)
                line = line.replace('\n ', ' ', 1).replace('\n', '', 1)
                file_doc = True
            else:
                line = OPEN_LINE.sub(r'\1/**', line, count=1)
        elif out and split_bare(line, out[-1]):
            line = split_bare(line, out[-1])
            out[-1] = ''
        elif split_names(line):
            line = split_names(line)
        elif TRAILING.match(line):
            line = TRAILING.sub(r'\1/**<', line, count=1)
        if line.startswith('#') and not file_doc and re.match(r'#\s*define\s+DEPTHAO_\w+_H\b', line):
            # a header without a description: still a documented file
            line += ' /** @file %s */' % name
            file_doc = True
        start = line.rfind('/*')
        if start >= 0 and '*/' not in line[start:]:
            in_comment = True
        out.append(line)
    return '\n'.join(out)


if __name__ == '__main__':
    with open(sys.argv[1], encoding='utf-8') as f:
        sys.stdout.write(filter_text(f.read(), os.path.basename(sys.argv[1])))
