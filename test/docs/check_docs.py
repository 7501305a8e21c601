#!/usr/bin/env python3
"""Checks the prose documentation (CONTRIBUTING.md, "Documentation"):

* no table cell over 300 characters in README.md, CONTRIBUTING.md, experiments/README.md,
  docs/**/*.md and examples/**/*.md (the generated
  parameter tables included: `scw params docs` puts a longer description under its table);
* every relative link and #anchor in those files resolves (a file or folder of the repository, a
  heading of the linked page as GitHub makes its anchor);
* docs/README.md links every page under docs/;
* README.md is at most 10 KB, opens with the two commands (the second is the one .ci/run runs)
  and its command table names every command `scw --help` lists (when SCW is given).

Usage: check_docs.py ROOT [SCW]     exit 1 with one line per problem
       check_docs.py --self-test     plant each kind of problem in a scratch tree
"""
import os
import re
import subprocess
import sys
import tempfile

MAX_CELL = 300
MAX_README = 10 * 1024
INSTALL_AND_TEST = ('.ci/install-deps && cmake --preset ci && cmake --build --preset ci && '
                    'ctest --preset ci')
INSTALL_AND_TUNE = ('.ci/install-deps && cmake --preset release && cmake --build --preset release '
                    '&& build/release/tuning/scw tune')
LINK = re.compile(r'(?<!!)\[([^\]]*)\]\(([^)\s]+)\)|!\[[^\]]*\]\(([^)\s]+)\)')
CODE_SPAN = re.compile(r'`[^`]*`')


def pages(root):
    out = [p for p in ('README.md', 'CONTRIBUTING.md', os.path.join('experiments', 'README.md'))
           if os.path.exists(os.path.join(root, p))]
    for top in ('docs', 'examples'):
        for d, _, files in os.walk(os.path.join(root, top)):
            out += [os.path.relpath(os.path.join(d, f), root) for f in sorted(files)
                    if f.endswith('.md')]
    return sorted(out)


def prose_lines(text):
    """(line number, line) outside fenced code blocks."""
    fence = None
    for n, line in enumerate(text.split('\n'), 1):
        s = line.lstrip()
        if s.startswith('```') or s.startswith('~~~'):
            mark = s[:3]
            fence = None if fence == mark else (mark if fence is None else fence)
            continue
        if fence is None:
            yield n, line


def cells(line):
    parts = re.split(r'(?<!\\)\|', line.strip())
    return [c.strip() for c in parts[1:-1]]


def anchors(text):
    """The anchors GitHub gives the headings of a page."""
    seen, out = {}, set()
    for _, line in prose_lines(text):
        m = re.match(r'#{1,6}\s+(.*?)\s*#*\s*$', line)
        if not m:
            continue
        title = re.sub(r'\[([^\]]*)\]\([^)]*\)', r'\1', m.group(1)).lower()
        slug = re.sub(r'[^\w\- ]', '', title).replace(' ', '-')
        k = seen.get(slug, 0)
        seen[slug] = k + 1
        out.add(slug if k == 0 else f'{slug}-{k}')
    for m in re.finditer(r'<a\s+(?:name|id)="([^"]+)"', text):
        out.add(m.group(1))
    return out


def check(root, scw=None):
    problems = []
    texts = {p: open(os.path.join(root, p), encoding='utf-8').read() for p in pages(root)}
    for page, text in texts.items():
        for n, line in prose_lines(text):
            if line.lstrip().startswith('|'):
                for c in cells(line):
                    if len(c) > MAX_CELL:
                        problems.append(f'{page}:{n}: a table cell of {len(c)} characters (at most '
                                        f'{MAX_CELL}; move the detail under the table): {c[:50]}…')
            for m in LINK.finditer(CODE_SPAN.sub('', line)):
                target = m.group(2) or m.group(3)
                if re.match(r'[a-z]+:', target):
                    continue  # http:, https:, mailto:
                path, _, anchor = target.partition('#')
                where = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
                full = os.path.join(root, where)
                if not os.path.exists(full):
                    problems.append(f'{page}:{n}: link to a missing file: {target}')
                    continue
                if anchor and where.endswith('.md'):
                    other = texts.get(where)
                    if other is None:
                        other = open(full, encoding='utf-8').read()
                    if anchor not in anchors(other):
                        problems.append(f'{page}:{n}: link to a missing heading: {target}')
    index = texts.get(os.path.join('docs', 'README.md'))
    if index is None:
        problems.append('docs/README.md: missing (the index of every page under docs/)')
    else:
        linked = {os.path.normpath(os.path.join('docs', m.group(2) or m.group(3) or '').split('#')[0])
                  for m in LINK.finditer(index)}
        for page in texts:
            if page.startswith('docs' + os.sep) and page != os.path.join('docs', 'README.md'):
                if page not in linked:
                    problems.append(f'docs/README.md: does not list {page}')
    readme = texts.get('README.md', '')
    size = len(readme.encode('utf-8'))
    if size > MAX_README:
        problems.append(f'README.md: {size} bytes, the front page has at most {MAX_README}')
    blocks = re.findall(r'```sh\n(.*?)```', readme, re.S)
    commands = [[l for l in b.split('\n') if l and not l.startswith('#')] for b in blocks[:2]]
    if commands != [[INSTALL_AND_TUNE], [INSTALL_AND_TEST]]:
        problems.append('README.md: the first two sh blocks must be exactly the two commands:\n  '
                        + INSTALL_AND_TUNE + '\n  ' + INSTALL_AND_TEST)
    ci = os.path.join(root, '.ci', 'run')
    if os.path.exists(ci) and INSTALL_AND_TEST.split('&& ', 1)[1] not in open(ci).read():
        problems.append(".ci/run: no longer runs the README's test command")
    if scw:
        help_text = subprocess.run([scw, '--help'], capture_output=True, text=True).stdout
        listed = re.search(r'Subcommands:\n(.*?)\n\n', help_text, re.S)
        names = re.findall(r'^  (\S+)', listed.group(1), re.M) if listed else []
        if not names:
            problems.append(f'{scw} --help: no commands found')
        for name in names:
            if not re.search(r'^\| `scw ' + re.escape(name) + r'\b', readme, re.M):
                problems.append(f'README.md: the command table has no row for scw {name}')
    return problems


def self_test():
    good_readme = ('# x\n\n```sh\n# 1.\n' + INSTALL_AND_TUNE + '\n```\n\n```sh\n# 2.\n' +
                   INSTALL_AND_TEST + '\n```\n\n| Command | What |\n| --- | --- |\n'
                   '| `scw tune` | tunes |\n\n[docs](docs/README.md)\n')
    tree = {
        'README.md': good_readme,
        'docs/README.md': '# Docs\n\n[a](a.md), [notes](notes/b.md)\n',
        'docs/a.md': '# A page\n\n## The part: one\n\n[b](notes/b.md#log), [self](#the-part-one)\n',
        'docs/notes/b.md': '# B\n\n## Log\n\n[up](../a.md#a-page)\n',
    }
    planted = {
        'docs/c.md': ('# C\n\n| a | b |\n| --- | --- |\n| ' + 'x' * 301 + ' | y |\n\n'
                      '[gone](gone.md) [no heading](a.md#nothing)\n'),
    }

    def run(files):
        with tempfile.TemporaryDirectory() as d:
            for rel, text in files.items():
                os.makedirs(os.path.dirname(os.path.join(d, rel)), exist_ok=True)
                with open(os.path.join(d, rel), 'w', encoding='utf-8') as f:
                    f.write(text)
            return check(d)

    ok = run(tree)
    if ok:
        print('self-test: a good tree was refused:\n' + '\n'.join(ok))
        return 1
    bad = run({**tree, **planted, 'README.md': good_readme.replace('ctest --preset ci', 'ctest')
               + 'y' * MAX_README})
    expected = ['a table cell of 301 characters', 'link to a missing file: gone.md',
                'link to a missing heading: a.md#nothing', 'does not list docs/c.md',
                'the front page has at most', 'the first two sh blocks']
    missing = [e for e in expected if not any(e in p for p in bad)]
    if missing:
        print('self-test: not reported: ' + ', '.join(missing) + '\ngot:\n' + '\n'.join(bad))
        return 1
    print('self-test: ok')
    return 0


def main():
    if sys.argv[1:] == ['--self-test']:
        return self_test()
    if len(sys.argv) not in (2, 3):
        print(__doc__)
        return 2
    problems = check(sys.argv[1], sys.argv[2] if len(sys.argv) == 3 else None)
    for p in problems:
        print(p)
    if not problems:
        print(f'docs: ok ({len(pages(sys.argv[1]))} pages)')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
