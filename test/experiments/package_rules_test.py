#!/usr/bin/env python3
"""The experiments package's shape (issue 48 item 5), checked on the source with `ast`: no Python
file in experiments/ over 600 lines, no function (or method) over 80 lines, and nothing but the
report's own entry point (experiments/report.py) imports the report (`scwexp.report` or the
script `report`); and experiments/README.md has one table row per command (every script with a
`__main__` entry and run_all.sh), none over 300 characters. Standard library only.

    python3 test/experiments/package_rules_test.py EXPERIMENTS_DIR
"""

import ast
import os
import sys

MAX_FILE_LINES = 600
MAX_FUNCTION_LINES = 80
MAX_ROW = 300                # characters of a README table row
REPORT_ENTRY = "report.py"   # the one file allowed to import the report


def python_files(root):
    """Every .py file under root (results/ and caches aside), sorted, as paths relative to root."""
    out = []
    for d, subdirs, files in os.walk(root):
        subdirs[:] = sorted(s for s in subdirs if s not in ("results", "__pycache__"))
        out += [os.path.relpath(os.path.join(d, f), root) for f in files if f.endswith(".py")]
    return sorted(out)


def long_functions(tree, limit=MAX_FUNCTION_LINES):
    """[(name, first line, lines)] of the functions longer than `limit` lines (decorators and
    docstring included: end_lineno − lineno + 1 of the def)."""
    out = []
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            n = node.end_lineno - node.lineno + 1
            if n > limit:
                out.append((node.name, node.lineno, n))
    return out


def imports_report(tree, rel):
    """The import statements of `tree` that reach the report: `import report`, `from report
    import ...`, `scwexp.report[...]` in any form, or a relative import of `report` from inside
    the package."""
    hits = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level and rel.startswith("scwexp" + os.sep):
                base = "scwexp" if os.path.dirname(rel) == "scwexp" or node.level == 1 else ""
                mod = f"{base}.{mod}" if mod else base
            names = [mod] + [f"{mod}.{a.name}" for a in node.names]
        else:
            continue
        for name in names:
            if name == "report" or name.startswith("report.") or name == "scwexp.report" \
                    or name.startswith("scwexp.report."):
                hits.append((node.lineno, name))
                break
    return hits


def violations(root):
    """Every breach of the three rules, one line each."""
    bad = []
    for rel in python_files(root):
        path = os.path.join(root, rel)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        n = len(text.splitlines())
        if n > MAX_FILE_LINES:
            bad.append(f"{rel}: {n} lines (at most {MAX_FILE_LINES})")
        tree = ast.parse(text, filename=path)
        for name, line, length in long_functions(tree):
            bad.append(f"{rel}:{line}: function {name} has {length} lines "
                       f"(at most {MAX_FUNCTION_LINES})")
        in_report = rel.startswith(os.path.join("scwexp", "report") + os.sep)
        if rel != REPORT_ENTRY and not in_report:
            for line, name in imports_report(tree, rel):
                bad.append(f"{rel}:{line}: imports the report ({name}); only {REPORT_ENTRY} may")
    return bad


def commands(root):
    """The entry points of experiments/: the scripts with a `__main__` block, and run_all.sh."""
    out = ["run_all.sh"] if os.path.exists(os.path.join(root, "run_all.sh")) else []
    for name in sorted(os.listdir(root)):
        if name.endswith(".py"):
            with open(os.path.join(root, name), encoding="utf-8") as f:
                if 'if __name__ == "__main__":' in f.read():
                    out.append(name)
    return out


def readme_problems(root):
    """README rows: one per command (its first cell names experiments/<command>), at most
    MAX_ROW characters each."""
    with open(os.path.join(root, "README.md"), encoding="utf-8") as f:
        lines = f.read().split("\n")
    bad, firsts = [], []
    for n, line in enumerate(lines, 1):
        if not line.startswith("|"):
            continue
        if len(line) > MAX_ROW:
            bad.append(f"README.md:{n}: a table row of {len(line)} characters (at most {MAX_ROW}; "
                       "details go to the script's docstring)")
        firsts.append(line.split("|")[1])
    for cmd in commands(root):
        rows = [c for c in firsts if f"experiments/{cmd}" in c]
        if len(rows) != 1:
            bad.append(f"README.md: {len(rows)} command rows for experiments/{cmd} (one expected)")
    return bad


def self_test():
    """The checker on small sources: a long function and a report import are found."""
    body = "\n".join(f"    x{i} = {i}" for i in range(MAX_FUNCTION_LINES))
    tree = ast.parse(f"def f():\n{body}\n\ndef g():\n    return 1\n")
    assert [x[0] for x in long_functions(tree)] == ["f"], long_functions(tree)
    for src in ("import report", "from report import main", "import scwexp.report",
                "from scwexp.report import claims", "from scwexp import report"):
        assert imports_report(ast.parse(src), "driver.py"), src
    assert imports_report(ast.parse("from . import report"), os.path.join("scwexp", "x.py"))
    for src in ("import scwexp", "from scwexp import claims", "import reporting"):
        assert not imports_report(ast.parse(src), "driver.py"), src


def main(argv):
    if len(argv) != 2:
        sys.exit("usage: package_rules_test.py EXPERIMENTS_DIR")
    self_test()
    bad = violations(argv[1]) + readme_problems(argv[1])
    for line in bad:
        print(f"FAIL: {line}")
    if bad:
        return 1
    print(f"ok: {len(python_files(argv[1]))} Python files within {MAX_FILE_LINES} lines, "
          f"functions within {MAX_FUNCTION_LINES}, the report imported by {REPORT_ENTRY} only, "
          f"a README row per command ({len(commands(argv[1]))})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
