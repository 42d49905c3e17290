#!/usr/bin/env python3
"""tests/api_names.py HEADER... -- the names the headers declare with INSTESS_API (functions and extern objects,
each declarator of a comma-separated list), one per line, sorted: what the shared library must export, no more
and no less (tests/install_check.sh compares them with `nm -D`).  A function prototype or extern object at file
scope without the mark is an error (it would be hidden in the library): named on stderr, exit status 1."""
import re
import sys

names = set()
unmarked = []
for path in sys.argv[1:]:
    text = re.sub(r'/\*.*?\*/', ' ', open(path).read(), flags=re.S)   # comments out
    for n, line in enumerate(text.split('\n'), 1):   # file-scope declarations start in column 0
        if re.match(r'(extern (?!"C")|(const |unsigned |struct |enum )*[A-Za-z_]\w*[ *]+\**[A-Za-z_]\w*\s*\()', line) \
                and not re.match(r'(typedef|static|INSTESS_API|extern INSTESS_API)\b', line):
            unmarked.append('%s:%d: %s' % (path, n, line.strip()))
    for m in re.finditer(r'\bINSTESS_API\b([^;{]*);', text):
        decl = m.group(1)
        if '(' in decl:   # a function: the name stands right before the first parenthesis
            names.add(re.search(r'([A-Za-z_]\w*)\s*$', decl[:decl.index('(')]).group(1))
            continue
        parts = re.sub(r'\[[^\]]*\]', '', decl).split(',')   # objects: "const T a, b[], *c"
        names.add(re.search(r'([A-Za-z_]\w*)\s*$', parts[0]).group(1))
        for p in parts[1:]:
            names.add(re.search(r'([A-Za-z_]\w*)', p).group(1))
print('\n'.join(sorted(names)))
for u in unmarked:
    print('declared without INSTESS_API: ' + u, file=sys.stderr)
sys.exit(1 if unmarked else 0)
