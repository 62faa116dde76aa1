#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Every relative link in README.md, HACKING.md and docs/**/*.md points to a file or
directory of the tree, and every #anchor to a heading of the file it names (GitHub's
slugs: lower case, punctuation dropped, spaces as dashes, -1, -2 ... for repeats); and
every docs/**/*.md is one click from the README (linked from README.md itself; docs/api/
is Doxygen's input).
Links inside code (fenced blocks, `inline`) are not links. External links (a scheme
such as https:, mailto:) are not checked.  Usage: check_links.py SOURCE_ROOT"""
import os
import re
import sys

FENCE = re.compile(r'^\s*(```|~~~)')
INLINE_CODE = re.compile(r'(`+)(?:(?!\1).)+?\1')
# [text](target "title") and ![alt](target); the text may hold one level of brackets
LINK = re.compile(r'!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+"[^"]*")?\s*\)')
REFDEF = re.compile(r'^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$')
HEADING = re.compile(r'^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$')
HTML_ID = re.compile(r'<a\s+(?:name|id)="([^"]+)"')


def prose_lines(text):
    """(line number, line) outside fenced code blocks, inline code removed."""
    fence = None
    for n, line in enumerate(text.split('\n'), 1):
        m = FENCE.match(line)
        if m:
            if fence is None:
                fence = m.group(1)
            elif m.group(1) == fence:
                fence = None
            continue
        if fence is None:
            yield n, INLINE_CODE.sub('', line)


def slug(heading):
    text = re.sub(r'!?\[([^\]]*)\]\([^)]*\)', r'\1', heading)  # links: their text
    text = re.sub(r'<[^>]+>', '', text).replace('`', '')
    text = text.strip().lower()
    text = ''.join(c for c in text if c.isalnum() or c in ' -_')
    return text.replace(' ', '-')


_anchors = {}


def anchors(path):
    if path not in _anchors:
        seen, out = {}, set()
        with open(path, encoding='utf-8') as f:
            text = f.read()
        fence = None
        for line in text.split('\n'):
            m = FENCE.match(line)
            if m:
                fence = m.group(1) if fence is None else (None if m.group(1) == fence else fence)
                continue
            if fence is not None:
                continue
            out.update(HTML_ID.findall(line))
            h = HEADING.match(line)
            if h:
                s = slug(h.group(2))
                k = seen.get(s, 0)
                seen[s] = k + 1
                out.add(s if k == 0 else '%s-%d' % (s, k))
        _anchors[path] = out
    return _anchors[path]


def documents(root):
    docs = [os.path.join(root, 'README.md'), os.path.join(root, 'HACKING.md')]
    for d, _, files in os.walk(os.path.join(root, 'docs')):
        docs += [os.path.join(d, f) for f in sorted(files) if f.endswith('.md')]
    return sorted(docs)


def check(root):
    errors, count, from_readme = [], 0, set()
    for doc in documents(root):
        if not os.path.isfile(doc):
            errors.append('%s: missing' % os.path.relpath(doc, root))
            continue
        with open(doc, encoding='utf-8') as f:
            text = f.read()
        for n, line in prose_lines(text):
            targets = LINK.findall(line)
            m = REFDEF.match(line)
            if m:
                targets.append(m.group(1))
            for t in targets:
                if not t or re.match(r'^[a-zA-Z][a-zA-Z0-9+.-]*:', t):
                    continue  # external (https:, mailto:, ...)
                count += 1
                where = '%s:%d' % (os.path.relpath(doc, root), n)
                path, _, anchor = t.partition('#')
                target = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
                if os.path.relpath(target, root).split(os.sep)[0] == '..':
                    errors.append('%s: %s leaves the source tree' % (where, t))
                    continue
                if not os.path.exists(target):
                    errors.append('%s: %s: no such file' % (where, t))
                    continue
                if doc == os.path.join(root, 'README.md'):
                    from_readme.add(target)
                if anchor and target.endswith('.md') and anchor not in anchors(target):
                    errors.append('%s: %s: no heading with the anchor #%s in %s'
                                  % (where, t, anchor, os.path.relpath(target, root)))
    for doc in documents(root):
        # docs/api/ is Doxygen's input (the reference's main page), not a page of its own
        if os.path.dirname(doc) != root and doc not in from_readme and \
                not doc.startswith(os.path.join(root, 'docs', 'api', '')):
            errors.append('%s: not linked from README.md' % os.path.relpath(doc, root))
    return errors, count


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    errors, count = check(os.path.abspath(sys.argv[1]))
    for e in errors:
        print('check_links: ' + e, file=sys.stderr)
    print('%d relative links checked, %d problems' % (count, len(errors)))
    return 1 if errors or count == 0 else 0


if __name__ == '__main__':
    sys.exit(main())
