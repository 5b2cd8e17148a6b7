#!/usr/bin/python3
"""tests/readme/run.py - every example of README.md runs as a test, verbatim (a user copies them first).

The README's fenced blocks are run in order, in one scratch directory where `hovox` and
`build/hovox-mpi` are the ones built, and `samples/` and `tests/` are the repository's:

- ```sh blocks: run as they stand (sh -e), each block must exit 0;
- ``` blocks of a transcript, lines `$ COMMAND` (continued by a trailing backslash) followed by
  what it prints: the command is run and its output (stdout and stderr) must match what the
  README shows, compared with runs of blanks and line breaks folded to one space (the README
  wraps long lines), `...` standing for any text (a line of its own: any lines), and a trailing
  `(exit N)` giving the exit code (else 0);
- ```lua blocks: run as a script by `hovox run`, with the scratch directory as arg[1].

HTML comments in the README (invisible when it is read) prepare what an example takes from the
user, so the example itself stays verbatim:
  <!-- test-setup: COMMANDS -->   run before the next block (sh -e; may span lines);
  <!-- test-file: NAME -->        the next block is written to NAME instead of run (a job file);
  <!-- test-skip: REASON -->      the next block is not run (needs a cluster, say); reported.

usage: run.py README.md --hovox build/hovox [--only SUBSTRING] [--keep]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

FENCE = re.compile(r'^```(\w*)\s*$')
DIRECTIVE = re.compile(r'<!--\s*test-(setup|file|skip):\s*(.*?)\s*-->', re.S)


def blocks(text):
    """(line, language, body, directives) for every fenced block, with the directives met since
    the block before."""
    lines = text.split('\n')
    out, pending, i = [], [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            # directives may span lines: look for one starting here
            if '<!--' in lines[i]:
                j = i
                chunk = lines[i]
                while '-->' not in chunk and j + 1 < len(lines):
                    j += 1
                    chunk += '\n' + lines[j]
                for d in DIRECTIVE.finditer(chunk):
                    pending.append((d.group(1), d.group(2)))
                i = j + 1
                continue
            i += 1
            continue
        lang, start = m.group(1), i + 1
        j = start
        while j < len(lines) and not FENCE.match(lines[j]):
            j += 1
        out.append((start, lang, '\n'.join(lines[start:j]), pending))
        pending = []
        i = j + 1
    return out


def transcript(body):
    """[(command, expected output lines)] of a block of `$ ` lines, or None."""
    lines = body.split('\n')
    if not lines or not lines[0].startswith('$ '):
        return None
    items, i = [], 0
    while i < len(lines):
        if not lines[i].startswith('$ '):
            return None
        cmd = lines[i][2:]
        while cmd.endswith('\\') and i + 1 < len(lines):
            i += 1
            cmd = cmd[:-1] + ' ' + lines[i].strip()
        i += 1
        exp = []
        while i < len(lines) and not lines[i].startswith('$ '):
            exp.append(lines[i])
            i += 1
        items.append((cmd, exp))
    return items


def pattern(expected):
    """A regex over the folded output, and the exit code the transcript shows."""
    text = ' '.join(expected)
    code = 0
    m = re.search(r'\(exit (\d+)\)\s*$', text)
    if m:
        code = int(m.group(1))
        text = text[:m.start()]
    folded = ' '.join(text.split())
    parts = [re.escape(p) for p in folded.split('...')]
    # "..." is any text; blanks next to it are optional (it may stand for nothing at a line's end)
    rx = r'\s*.*?\s*'.join(p.strip('\\ ') if p.strip() else '' for p in parts)
    return re.compile(r'^\s*' + rx + r'\s*$', re.S), code


def run_sh(script, cwd, env, timeout):
    return subprocess.run(['sh', '-e', '-c', script], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('readme')
    ap.add_argument('--hovox', required=True)
    ap.add_argument('--only', default='')
    ap.add_argument('--keep', action='store_true')
    ap.add_argument('--timeout', type=float, default=900)
    a = ap.parse_args()
    repo = os.path.dirname(os.path.abspath(a.readme))
    hovox = os.path.abspath(a.hovox)
    build = os.path.dirname(hovox)
    scratch = tempfile.mkdtemp(prefix='hovox-readme-')
    bindir = os.path.join(scratch, '.bin')
    os.mkdir(bindir)
    os.symlink(hovox, os.path.join(bindir, 'hovox'))
    for d in ('samples', 'tests'):
        os.symlink(os.path.join(repo, d), os.path.join(scratch, d))
    os.symlink(build, os.path.join(scratch, 'build'))
    env = dict(os.environ, PATH=bindir + os.pathsep + os.environ.get('PATH', ''),
               OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1')  # as the README says for one machine
    text = open(a.readme, encoding='utf-8').read()
    passed = failed = skipped = 0
    for line, lang, body, directives in blocks(text):
        where = 'README.md:%d' % line
        if a.only and a.only not in body:
            continue
        if 'make demo' in body and 'make test' in body:
            continue  # the quick start is what runs this
        skip = [v for k, v in directives if k == 'skip']
        if skip:
            print('%s: skipped (%s)' % (where, skip[0]))
            skipped += 1
            continue
        t0 = time.time()
        ok, why = True, ''
        try:
            for k, v in directives:
                if k == 'setup':
                    r = run_sh(v, scratch, env, a.timeout)
                    if r.returncode != 0:
                        ok, why = False, 'setup failed (%d): %s%s' % (r.returncode, r.stdout[-800:], r.stderr[-800:])
                        break
            files = [v for k, v in directives if k == 'file']
            if not ok:
                pass
            elif files:
                with open(os.path.join(scratch, files[0]), 'w') as f:
                    f.write(body + '\n')
            elif lang == 'sh':
                r = run_sh(body, scratch, env, a.timeout)
                if r.returncode != 0:
                    ok, why = False, 'exit %d\n%s%s' % (r.returncode, r.stdout[-1500:], r.stderr[-1500:])
            elif lang == 'lua':
                with open(os.path.join(scratch, '.example.lua'), 'w') as f:
                    f.write(body + '\n')
                r = run_sh('hovox run .example.lua .', scratch, env, a.timeout)
                if r.returncode != 0:
                    ok, why = False, 'exit %d\n%s%s' % (r.returncode, r.stdout[-1500:], r.stderr[-1500:])
            elif lang == '':
                items = transcript(body)
                if items is None:
                    continue  # output shown without a command, a layout, a table: nothing to run
                for cmd, exp in items:
                    rx, code = pattern(exp)
                    r = run_sh(cmd, scratch, env, a.timeout)
                    got = ' '.join((r.stdout + r.stderr).split())
                    if r.returncode != code or not rx.match(got):
                        ok = False
                        why += '$ %s\nexit %d (expected %d); printed:\n%s\n' % (cmd, r.returncode, code,
                                                                               (r.stdout + r.stderr)[-2000:])
            else:
                continue  # json and others are data, written by test-file where an example uses them
        except subprocess.TimeoutExpired:
            ok, why = False, 'timed out after %g s' % a.timeout
        if ok:
            passed += 1
            print('%s: ok (%.1f s)' % (where, time.time() - t0))
        else:
            failed += 1
            print('%s: FAILED\n%s' % (where, why.rstrip()))
    print('readme: %d passed, %d failed, %d skipped%s' % (passed, failed, skipped,
                                                          (' (kept %s)' % scratch) if a.keep else ''))
    if not a.keep:
        shutil.rmtree(scratch, ignore_errors=True)
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
