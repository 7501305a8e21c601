#!/usr/bin/env python3
"""Checks the layering of the source tree (docs/architecture.md): what each folder may include,
that no model opens files, and that every library source is listed in its CMakeLists.txt.

Usage: check_layers.py ROOT          check the tree at ROOT (exit 1 with one line per violation)
       check_layers.py --self-test   plant violations in a scratch tree and require that each is
                                     reported (so the check itself cannot silently pass)
"""
import os
import re
import sys
import tempfile

# (folder prefix, forbidden include pattern, why[, exempt prefixes]). A folder inherits the rules
# of its prefixes, except where it is exempt.
YAML = (r'<yaml-cpp/|<yaml\.h>', 'YAML belongs to scw::params')
NLOPT = (r'<nlopt', 'NLopt belongs to the optimisation (and the racing line in scw::planning)')
IPOPT = (r'<Ip[A-Z]\w*\.hpp>|<coin/|<HSLLoader\.h>', 'Ipopt belongs to scw::motion')
# MPI: only the execution layer's MPI back end includes <mpi.h> (checked over every library file).
MPI_FILE = 'tuning/exec/mpi_backend.cc'
MPI = (r'<mpi\.h>', f'MPI belongs to {MPI_FILE} alone (the execution layer)')
THREADS = (r'<(thread|future|condition_variable)>', 'models create no threads')
FILES = (r'<(fstream|filesystem)>', 'models open no files')
# Planning runs offline, at preparation time: it may use NLopt (the racing line), the plant (track
# geometry, the quasi-steady envelope) and a lock and futures (the cache shared by the threads
# that prepare scenarios), but starts no threads and opens no files.
PLANNING = ('controller/planning/',)
RULES = [
    ('controller/', YAML), ('controller/', NLOPT, PLANNING),
    ('controller/', THREADS, PLANNING), ('controller/', FILES),
    ('controller/', (r'"(tuning|params/io)/', 'controllers know no simulation or file I/O')),
    ('controller/', (r'"plant/', 'controllers know no plant'), PLANNING),
    ('controller/planning/', (r'<(thread|condition_variable)>', 'planning starts no threads')),
    ('controller/common/', IPOPT), ('controller/stability/', IPOPT),
    ('controller/common/', (r'"controller/(stability|motion|planning)/', 'common/ is the bottom layer')),
    ('controller/stability/', (r'"controller/(motion|planning)/', 'scw::stability ships alone to the car')),
    ('controller/stability/', (r'<mutex>|<atomic>', 'the car\'s controller takes no locks')),
    ('controller/planning/', IPOPT), ('controller/planning/', (r'"controller/(motion|stability)/', 'planning sits below motion')),
    ('plant/', YAML), ('plant/', NLOPT), ('plant/', IPOPT), ('plant/', THREADS),
    ('plant/', FILES), ('plant/', (r'<mutex>', 'models take no locks')),
    ('plant/', (r'"(tuning|controller|params/io)/', 'the plant knows no controller, simulation or file I/O')),
    ('params/schema/', YAML), ('params/schema/', (r'"(params/io|tuning|controller|plant)/', 'the schema is the bottom layer')),
    ('tuning/exec/', (r'"(tuning/(?!exec/)|controller/|plant/)', 'the execution layer knows no simulation or optimisation: a job is an index, its result bytes')),
    ('tuning/sim/', (r'"tuning/(optim|cli|sweep|replay|maneuver)/', 'simulation sits below the sweep, the replay, the maneuvers, optimisation and the CLI')),
    ('tuning/sweep/', (r'"tuning/(optim|cli|replay|maneuver)/', 'the sweep sits on simulation and the execution layer, below the CLI')),
    ('tuning/replay/', (r'"tuning/(optim|cli|sweep|maneuver|exec)/', 'the replay sits on simulation, below the CLI')),
    ('tuning/maneuver/', (r'"tuning/(optim|cli|sweep|replay)/', 'maneuvers sit below optimisation and the CLI')),
    ('tuning/optim/', (r'"tuning/(cli|sweep|replay)/', 'the CLI sits on top; optimisation needs no sweep or replay')),
]
# scw::io (plain files) sits in params/io beside the YAML code: these files may not use YAML.
IO_FILES = ('params/io/atomic_file', 'params/io/csv', 'params/io/text', 'params/io/sha256',
            'params/io/suggest', 'params/io/test_fault')
IO_RULES = [YAML, (r'"params/io/(load|write|yaml_doc|docs|ros2_check|stability_lint)\.h"', 'scw::io is below scw::params')]
# Drawing is the CLI's (tuning/cli/python_script.cc runs the plot scripts): outside tuning/cli no
# source starts a process that runs Python, and no plot script lives there. Starting processes as
# such is allowed (the sweep's workers are `scw` itself).
SPAWN_CALL = re.compile(r'\b(posix_spawnp?|popen|system|fork|vfork|exec[lv]p?e?)\s*\(')
PYTHON = re.compile(r'python|matplotlib|\.py\b', re.I)
DRAWING_HOME = 'tuning/cli/'
# Calls that open files, forbidden in the models whatever the include.
OPEN_CALL = re.compile(r'\b(fopen|freopen|std::ifstream|std::ofstream|std::fstream|::open\s*\()')
LIBRARY_FOLDERS = ('controller', 'plant', 'params', 'tuning')
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"][^>"]+[>"])', re.M)


def sources(root):
    for top in LIBRARY_FOLDERS:
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in sorted(files):
                if f.endswith(('.h', '.cc', '.in', '.py')):
                    p = os.path.join(d, f)
                    yield os.path.relpath(p, root).replace(os.sep, '/'), p


def strip_comments(text):
    text = re.sub(r'/\*.*?\*/', '', text, flags=re.S)
    return re.sub(r'//[^\n]*', '', text)


def check(root):
    problems = []
    for rel, path in sources(root):
        if rel.endswith('.py'):
            if not rel.startswith(DRAWING_HOME):
                problems.append(f'{rel}: a script in a library: libraries never draw (plot scripts '
                                f'belong to {DRAWING_HOME})')
            continue
        text = open(path, encoding='utf-8', errors='replace').read()
        code = strip_comments(text)
        includes = INCLUDE.findall(text)
        rules = [rule[1] for rule in RULES
                 if rel.startswith(rule[0]) and not (len(rule) > 2 and rel.startswith(rule[2]))]
        if rel.startswith(IO_FILES):
            rules += IO_RULES
        if rel != MPI_FILE:
            rules.append(MPI)
        for pattern, why in rules:
            for inc in includes:
                if re.search(pattern, inc):
                    problems.append(f'{rel}: includes {inc}: {why}')
        if not rel.startswith(DRAWING_HOME) and SPAWN_CALL.search(code) and PYTHON.search(code):
            problems.append(f'{rel}: spawns a process to draw ({SPAWN_CALL.search(code).group(0)} '
                            f'and Python): libraries never draw, {DRAWING_HOME} does')
        if rel.startswith(('plant/', 'controller/')) and OPEN_CALL.search(code):
            problems.append(f'{rel}: opens a file ({OPEN_CALL.search(code).group(0)}): models open no files')
    # Every library .cc is named in a CMakeLists.txt of its folder or a parent, and no library
    # folder globs its sources.
    for top in LIBRARY_FOLDERS:
        for d, _, files in os.walk(os.path.join(root, top)):
            if 'CMakeLists.txt' in files:
                cm = open(os.path.join(d, 'CMakeLists.txt')).read()
                if re.search(r'file\s*\(\s*GLOB', strip_cmake_comments(cm)):
                    problems.append(f'{os.path.relpath(os.path.join(d, "CMakeLists.txt"), root)}: '
                                    'globs its sources: list them explicitly')
            for f in files:
                if not f.endswith('.cc'):
                    continue
                if not listed(root, os.path.join(d, f)):
                    problems.append(f'{os.path.relpath(os.path.join(d, f), root)}: not listed in any '
                                    'CMakeLists.txt of its folder or above (never built)')
    return problems + python_import_cycles(root)


def python_import_cycles(root):
    """Import cycles among the scripts of experiments/ (one module importing another that,
    directly or not, imports it back)."""
    folder = os.path.join(root, 'experiments')
    if not os.path.isdir(folder):
        return []
    import ast
    mods = {f[:-3] for f in os.listdir(folder) if f.endswith('.py')}
    graph = {}
    for m in sorted(mods):
        tree = ast.parse(open(os.path.join(folder, m + '.py'), encoding='utf-8').read())
        deps = set()
        for n in ast.walk(tree):  # also imports inside functions
            if isinstance(n, ast.Import):
                deps |= {a.name.split('.')[0] for a in n.names}
            elif isinstance(n, ast.ImportFrom) and n.module and not n.level:
                deps.add(n.module.split('.')[0])
        graph[m] = sorted(deps & mods)
    problems, state = [], {}

    def visit(m, stack):
        state[m] = 1
        for d in graph[m]:
            if state.get(d) == 1:
                cycle = stack[stack.index(d):] + [d]
                problems.append('experiments/: import cycle ' + ' -> '.join(cycle))
            elif d not in state:
                visit(d, stack + [d])
        state[m] = 2
    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    return problems


def strip_cmake_comments(text):
    return re.sub(r'#[^\n]*', '', text)


def listed(root, cc):
    d = os.path.dirname(cc)
    root = os.path.abspath(root)
    while True:
        cm = os.path.join(d, 'CMakeLists.txt')
        if os.path.exists(cm):
            rel = os.path.relpath(cc, d).replace(os.sep, '/')
            if re.search(r'(?<![\w/.])' + re.escape(rel) + r'(?![\w])', strip_cmake_comments(open(cm).read())):
                return True
        if os.path.abspath(d) == root:
            return False
        d = os.path.dirname(d)


def self_test():
    planted = {
        'controller/stability/bad.cc': '#include <IpIpoptApplication.hpp>\n',
        'controller/stability/bad2.cc': '#include "controller/motion/pmpc.h"\n',
        'controller/stability/bad3.cc': '#include "controller/planning/reference.h"\n',
        'controller/motion/bad.cc': '#include <nlopt.hpp>\n',
        'controller/motion/bad2.cc': '#include "plant/track/track.h"\n',
        'controller/planning/bad.cc': '#include <thread>\n',
        'controller/planning/bad2.cc': '#include "controller/motion/pmpc.h"\n',
        'controller/planning/bad3.cc': 'void F() { std::ofstream out("x"); }\n',
        'controller/planning/ok.cc': '#include <nlopt.hpp>\n#include <future>\n#include "plant/track/track.h"\n',
        'controller/common/bad.cc': '#include <yaml-cpp/yaml.h>\n',
        'plant/vehicle/bad.cc': 'void F() { std::ifstream in("x"); }\n',
        'plant/tire/bad.cc': '#include <fstream>\n',
        'params/io/csv.cc': '#include <yaml-cpp/yaml.h>\n',
        'tuning/sim/bad.cc': '#include "tuning/optim/tuner.h"\n',
        'tuning/sim/bad2.cc': '#include "tuning/sweep/sweep.h"\n',
        'tuning/exec/bad.cc': '#include "tuning/sim/closed_loop.h"\n',
        'tuning/exec/mpi_backend.cc': '#include <mpi.h>\n',
        'tuning/optim/bad.cc': '#include <mpi.h>\n',
        'controller/motion/bad_mpi.cc': '#include <mpi.h>\n',
        'tuning/optim/CMakeLists.txt': 'file(GLOB X *.cc)\n',
        'experiments/a.py': 'import b\n',
        'experiments/b.py': 'def f():\n    import a\n',
        'tuning/optim/bad_plot.cc': 'void F() { popen("python3 - plots.py", "w"); }\n',
        'tuning/optim/plots.py': 'import matplotlib\n',
        # Allowed: the CLI runs Python; a library starts `scw` workers.
        'tuning/cli/draw.cc': 'void F() { posix_spawnp(0, "python3", 0, 0, 0, 0); }\n',
        'tuning/cli/draw.py': 'import matplotlib\n',
        'tuning/sim/workers.cc': 'void F() { posix_spawn(0, "scw", 0, 0, 0, 0); }\n',
    }
    with tempfile.TemporaryDirectory() as root:
        for rel, text in planted.items():
            os.makedirs(os.path.join(root, os.path.dirname(rel)), exist_ok=True)
            open(os.path.join(root, rel), 'w').write(text)
        open(os.path.join(root, 'CMakeLists.txt'), 'w').write(
            ' '.join(r for r in planted if r.endswith('.cc') and r != 'tuning/sim/bad.cc'))
        found = check(root)
    expected = ['controller/stability/bad.cc: includes <IpIpoptApplication.hpp>',
                'controller/stability/bad2.cc: includes "controller/motion/pmpc.h"',
                'controller/stability/bad3.cc: includes "controller/planning/reference.h"',
                'controller/motion/bad.cc: includes <nlopt.hpp>',
                'controller/motion/bad2.cc: includes "plant/track/track.h"',
                'controller/planning/bad.cc: includes <thread>',
                'controller/planning/bad2.cc: includes "controller/motion/pmpc.h"',
                'controller/planning/bad3.cc: opens a file',
                'controller/common/bad.cc: includes <yaml-cpp/yaml.h>',
                'plant/vehicle/bad.cc: opens a file', 'plant/tire/bad.cc: includes <fstream>',
                'params/io/csv.cc: includes <yaml-cpp/yaml.h>',
                'tuning/sim/bad.cc: includes "tuning/optim/tuner.h"',
                'tuning/sim/bad2.cc: includes "tuning/sweep/sweep.h"',
                'tuning/exec/bad.cc: includes "tuning/sim/closed_loop.h"',
                'tuning/optim/bad.cc: includes <mpi.h>',
                'controller/motion/bad_mpi.cc: includes <mpi.h>',
                'tuning/optim/CMakeLists.txt: globs its sources',
                'tuning/sim/bad.cc: not listed',
                'experiments/: import cycle a -> b -> a',
                'tuning/optim/bad_plot.cc: spawns a process to draw',
                'tuning/optim/plots.py: a script in a library']
    allowed = ['tuning/cli/draw.cc', 'tuning/cli/draw.py', 'tuning/sim/workers.cc']
    missing = [e for e in expected if not any(f.startswith(e) for f in found)]
    # The one file allowed MPI must not be reported.
    missing += [f'(no report for) {f}' for f in found if f.startswith('tuning/exec/mpi_backend.cc')]
    for e in missing:
        print(f'self-test: the planted violation "{e}" was not reported, or a legal file was')
    wrong = [f for f in found if f.startswith(tuple(allowed))]
    for f in wrong:
        print(f'self-test: an allowed planted file was reported: {f}')
    # What planning may include is not reported (its exemptions hold).
    planning_ok = [f for f in found if f.startswith('controller/planning/ok.cc')]
    for f in planning_ok:
        print(f'self-test: reported what planning may include: {f}')
    return 1 if missing or wrong or planning_ok else 0


def main():
    if len(sys.argv) == 2 and sys.argv[1] == '--self-test':
        return self_test()
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    problems = check(sys.argv[1])
    for p in problems:
        print(p)
    print(f'layers: {len(problems)} violation(s)')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
