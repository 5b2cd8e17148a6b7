#!/usr/bin/python3
"""scripts/long_functions.py - functions longer than a limit (default 120 lines) in the C sources:
issue 26's rule (no function over 120 lines outside numeric kernels; a kernel that stays longer
says why in its banner, with a line 'long-function: NAME: REASON' in its file)."""
import re, sys, os

LIMIT = int(sys.argv[1]) if len(sys.argv) > 1 else 120
roots = ['src', 'volumes', 'slicing', 'renderer']
head = re.compile(r'^(?!static\s+const\b)[A-Za-z_][\w \*\(\),\[\]]*?\b(\w+)\s*\([^;]*$')
found = []
for root in roots:
    for d, _, fs in os.walk(root):
        for f in fs:
            if not f.endswith(('.c', '.cpp', '.inc')):
                continue
            p = os.path.join(d, f)
            lines = open(p, encoding='utf-8', errors='replace').read().split('\n')
            excused = set(m.group(1) for m in re.finditer(r'long-function:\s*(\w+)', '\n'.join(lines)))
            i = 0
            while i < len(lines):
                l = lines[i]
                m = head.match(l)
                if m and not l.startswith((' ', '\t', '#', '/', '*', '}')):
                    name = m.group(1)
                    j = i
                    while j < len(lines) and '{' not in lines[j] and not lines[j].rstrip().endswith(';'):
                        j += 1
                    if j < len(lines) and lines[j].rstrip().endswith(';'):
                        i = j + 1
                        continue
                    depth, k, started = 0, j, False
                    while k < len(lines):
                        depth += lines[k].count('{') - lines[k].count('}')
                        if '{' in lines[k]:
                            started = True
                        if started and depth <= 0:
                            break
                        k += 1
                    n = k - i + 1
                    if n > LIMIT and name not in excused:
                        found.append((n, p, i + 1, name))
                    i = k + 1
                    continue
                i += 1
for n, p, line, name in sorted(found, reverse=True):
    print('%4d  %s:%d  %s' % (n, p, line, name))
print('%d functions over %d lines' % (len(found), LIMIT), file=sys.stderr)
