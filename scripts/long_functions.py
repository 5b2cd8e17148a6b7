#!/usr/bin/python3
"""scripts/long_functions.py - functions longer than a limit (default 120 lines) in the C sources:
issue 26's rule (no function over 120 lines outside numeric kernels; a kernel that stays longer
says why in its banner, with a line 'long-function: NAME: REASON' in its file).

usage: long_functions.py [LIMIT] [--roots DIR ...]   list them; exit 1 when there is one
       long_functions.py --self-test                  check the finder on made-up files
`make long-function-tests` runs both (and so `make test`)."""
import os, re, sys, tempfile

HEAD = re.compile(r'^(?!static\s+const\b)[A-Za-z_][\w \*\(\),\[\]]*?\b(\w+)\s*\([^;]*$')
CHARS = re.compile(r"'(?:[^'\\]|\\.)+'")     # character literals
STRINGS = re.compile(r'"(?:[^"\\]|\\.)*"')   # string literals
EXCUSE = re.compile(r'long-function:\s*(\w+):\s*[A-Za-z]')  # a name and a reason in words


def long_functions(roots, limit):
    """(lines, path, first line, name) of every unexcused function over limit lines under roots."""
    found = []
    for root in roots:
        for d, _, fs in os.walk(root):
            for f in sorted(fs):
                if not f.endswith(('.c', '.cpp', '.inc')):
                    continue
                p = os.path.join(d, f)
                text = open(p, encoding='utf-8', errors='replace').read()
                found += file_functions(p, text, limit)
    return sorted(found, reverse=True)


def file_functions(p, text, limit):
    lines = text.split('\n')
    excused = set(m.group(1) for m in EXCUSE.finditer(text))
    found, i = [], 0
    while i < len(lines):
        l = lines[i]
        m = HEAD.match(l)
        if not m or l.startswith((' ', '\t', '#', '/', '*', '}')):
            i += 1
            continue
        name = m.group(1)
        j = i
        while j < len(lines) and '{' not in lines[j] and not lines[j].rstrip().endswith(';'):
            j += 1
        if j < len(lines) and lines[j].rstrip().endswith(';'):  # a declaration
            i = j + 1
            continue
        depth, k, started = 0, j, False
        while k < len(lines):
            code = CHARS.sub("' '", STRINGS.sub('""', lines[k]))  # braces in '{' and "{" are not blocks
            depth += code.count('{') - code.count('}')
            started |= '{' in code
            if started and depth <= 0:
                break
            k += 1
        n = k - i + 1
        if n > limit and name not in excused:
            found.append((n, p, i + 1, name))
        i = k + 1
    return found


def self_test():
    """A long function is found with its length; a short one, a declaration and a kernel whose
    banner gives a reason are not; an excuse without a reason excuses nothing."""
    def fn(name, body_lines):
        return 'static int %s(int a)\n{\n' % name + '    a += 1;\n' * body_lines + '    return a;\n}\n'
    files = {
        'long.c': '/* long.c - test */\n' + fn('too_long', 120) + fn('short_one', 10) + 'int decl(int a);\n',
        'kernel.c': '/* kernel.c - test\n * long-function: kernel: one pass over the data, split it costs 2x */\n' +
                    fn('kernel', 200),
        'bare.c': '/* long-function: bare: */\n' + fn('bare', 130),
    }
    with tempfile.TemporaryDirectory() as d:
        for f, t in files.items():
            open(os.path.join(d, f), 'w').write(t)
        got = sorted((n, os.path.basename(p), name) for n, p, _, name in long_functions([d], 120))
    want = [(124, 'long.c', 'too_long'), (134, 'bare.c', 'bare')]
    if got != want:
        print('long_functions.py self-test: got %s, want %s' % (got, want), file=sys.stderr)
        return 1
    print('long_functions.py self-test: ok')
    return 0


def main(argv):
    if argv[:1] == ['--self-test']:
        return self_test()
    roots = ['src', 'volumes', 'slicing', 'renderer']
    if '--roots' in argv:
        k = argv.index('--roots')
        roots, argv = argv[k + 1:], argv[:k]
    limit = int(argv[0]) if argv else 120
    found = long_functions(roots, limit)
    for n, p, line, name in found:
        print('%4d  %s:%d  %s' % (n, p, line, name))
    print('%d functions over %d lines' % (len(found), limit), file=sys.stderr)
    if found:
        print('split them into named helpers (STYLE.md), or, for a numeric kernel, say why in the '
              "file's banner: 'long-function: NAME: REASON'", file=sys.stderr)
    return 1 if found else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
