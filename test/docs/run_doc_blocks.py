#!/usr/bin/env python3
"""Runs the shell blocks a documentation page marks as runnable, so the page cannot rot.

A fenced ```sh block runs when the line before it (blank lines aside) is

    <!-- test: run -->              the block must exit 0
    <!-- test: run, exit 0 1 -->    any of the listed exit codes is accepted

The blocks run in order, each in its own `bash -e -o pipefail`, all in one scratch folder that
looks like the repository root (the page's commands are written for it): a copy of examples/,
links to the other top-level folders, the `scw` under test first on PATH and a preparation cache
of its own. Each --sub REGEX=TEXT is applied to every block first, so that a tune in a tutorial
stays a test (`--sub '--max-evals [0-9]+=--max-evals 4'`).

Usage: run_doc_blocks.py ROOT SCW WORKDIR PAGE [--sub REGEX=TEXT ...] [--expect FILE ...]
  PAGE      the page, relative to ROOT (docs/tutorial-own-track.md)
  --expect  files (relative to WORKDIR) that must exist afterwards
Exit 0 when every block exits as marked and every expected file exists, 1 otherwise.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import time

MARK = re.compile(r'<!--\s*test:\s*run(?:,\s*exit\s+([\d ]+))?\s*-->')


def blocks(text):
    """(line, accepted exit codes, script) of each marked sh block."""
    out = []
    lines = text.split('\n')
    i = 0
    while i < len(lines):
        if lines[i].strip() == '```sh':
            j = i - 1
            while j >= 0 and not lines[j].strip():
                j -= 1
            m = MARK.fullmatch(lines[j].strip()) if j >= 0 else None
            end = i + 1
            while end < len(lines) and lines[end].strip() != '```':
                end += 1
            if m:
                codes = [int(c) for c in m.group(1).split()] if m.group(1) else [0]
                out.append((i + 1, codes, '\n'.join(lines[i + 1:end])))
            i = end
        i += 1
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('root')
    ap.add_argument('scw')
    ap.add_argument('workdir')
    ap.add_argument('page')
    ap.add_argument('--sub', action='append', default=[])
    ap.add_argument('--expect', nargs='*', default=[])
    a = ap.parse_args()
    root = os.path.abspath(a.root)
    text = open(os.path.join(root, a.page), encoding='utf-8').read()
    todo = blocks(text)
    if not todo:
        print(f'{a.page}: no block marked <!-- test: run -->')
        return 1
    work = os.path.abspath(a.workdir)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    for entry in sorted(os.listdir(root)):
        if entry == 'examples':
            shutil.copytree(os.path.join(root, entry), os.path.join(work, entry))
        elif not entry.startswith('.') and entry != 'build':
            os.symlink(os.path.join(root, entry), os.path.join(work, entry))
    subs = [s.split('=', 1) for s in a.sub]
    env = dict(os.environ)
    env['PATH'] = os.path.dirname(os.path.abspath(a.scw)) + os.pathsep + env.get('PATH', '')
    env['SCW_CACHE_DIR'] = os.path.join(work, 'cache')
    t0 = time.monotonic()
    failed = 0
    for line, codes, script in todo:
        for pattern, text in subs:
            script = re.sub(pattern, text, script)
        print(f'--- {a.page}:{line}\n{script}', flush=True)
        t = time.monotonic()
        r = subprocess.run(['bash', '-e', '-o', 'pipefail', '-c', script], cwd=work, env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        print(r.stdout, end='')
        print(f'--- exit {r.returncode} in {time.monotonic() - t:.1f} s', flush=True)
        if r.returncode not in codes:
            print(f'{a.page}:{line}: the block exited {r.returncode}, expected '
                  f'{" or ".join(map(str, codes))}')
            failed += 1
    for f in a.expect:
        if not os.path.exists(os.path.join(work, f)):
            print(f'{a.page}: expected {f} after the blocks ran; it is missing')
            failed += 1
    print(f'{a.page}: {len(todo)} blocks in {time.monotonic() - t0:.1f} s'
          + ('' if not failed else f', {failed} problem(s)'))
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
