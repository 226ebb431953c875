#!/usr/bin/env python3
"""libdeferred's layers, enforced (docs/development.md, "Layers of libdeferred").

Every source and header of libdeferred sits in a layer folder (libdeferred/src/<layer>/,
include/dhdr/deferred/<layer>/); a layer includes only itself and the layers below it, in the
order of the docs' table; no two files of the library include each other's module (a module
is a header and the source of the same name), so no include loop hides inside a layer; libio
and libtonemap include nothing of libdeferred. Prints each violation and exits 1.

  check_layers.py SOURCE_DIR            check the tree
  check_layers.py SOURCE_DIR --self-test  check copies of the tree with a wrong-way include,
                                        a loop and a stray file added: each must fail
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

MAX_FILES = 20
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)


def layer_order(root):
    """The layers bottom up, from the table under the docs' heading."""
    text = open(os.path.join(root, 'docs', 'development.md'), encoding='utf-8').read()
    start = text.find('## Layers of libdeferred')
    if start < 0:
        sys.exit('check_layers: docs/development.md has no "## Layers of libdeferred" section')
    layers = []
    for line in text[start:].splitlines()[1:]:
        if line.startswith('## '):
            break
        m = re.match(r'\|\s*\d+\s*\|\s*`([a-z]+)`\s*\|', line)
        if m:
            layers.append(m.group(1))
    if not layers:
        sys.exit('check_layers: no layer rows (| n | `name` | …) in the docs\' table')
    return layers


def library_files(root):
    """(path, layer or None) of every file of libdeferred's sources and public headers."""
    out = []
    for base in ('libdeferred/src', 'include/dhdr/deferred'):
        top = os.path.join(root, base)
        for entry in sorted(os.listdir(top)):
            path = os.path.join(top, entry)
            if os.path.isfile(path):
                out.append((os.path.join(base, entry), None))
                continue
            for dirpath, _, files in os.walk(path):
                for f in sorted(files):
                    rel = os.path.relpath(os.path.join(dirpath, f), root)
                    out.append((rel, entry))
    return out


def included_layer(root, inc, own_dir, known):
    """The layer an include names, or None when it is not libdeferred's."""
    m = re.match(r'dhdr/deferred/([a-z_]+)/', inc)
    if m:
        return m.group(1)
    first = inc.split('/')[0]
    if '/' in inc and first in known:  # a private header, "layer/name.h"
        return first
    if '/' not in inc and os.path.isfile(os.path.join(root, own_dir, inc)):
        return 'same-folder'
    return None


def check(root):
    layers = layer_order(root)
    rank = {name: i for i, name in enumerate(layers)}
    problems = []
    files = library_files(root)
    counts = {}
    modules = {}  # module key -> set of module keys it includes
    for rel, layer in files:
        if layer is None:
            problems.append(f'{rel}: a file outside every layer folder')
            continue
        if layer not in rank:
            problems.append(f'{rel}: folder "{layer}" is not a layer of docs/development.md')
            continue
        folder = os.path.dirname(rel)
        counts[folder] = counts.get(folder, 0) + 1
        if not rel.endswith(('.h', '.cpp')):
            continue
        key = (layer, os.path.splitext(os.path.basename(rel))[0])
        deps = modules.setdefault(key, set())
        text = open(os.path.join(root, rel), encoding='utf-8').read()
        for inc in INCLUDE.findall(text):
            target = included_layer(root, inc, folder, rank)
            if target is None:
                continue
            if target == 'same-folder':
                problems.append(f'{rel}: #include "{inc}" names no layer (write "{layer}/{inc}")')
                continue
            if target not in rank:
                problems.append(f'{rel}: #include "{inc}": "{target}" is not a layer')
                continue
            if rank[target] > rank[layer]:
                problems.append(f'{rel}: #include "{inc}" points up, from layer {layer} '
                                f'({rank[layer] + 1}) to layer {target} ({rank[target] + 1})')
            dep = (target, os.path.splitext(os.path.basename(inc))[0])
            if dep != key:
                deps.add(dep)
    for folder, n in sorted(counts.items()):
        if n > MAX_FILES:
            problems.append(f'{folder}: {n} files, more than {MAX_FILES}')
    for a, deps in sorted(modules.items()):
        for b in sorted(deps):
            if a < b and a in modules.get(b, set()):
                problems.append(f'modules {a[0]}/{a[1]} and {b[0]}/{b[1]} include each other')
    for lib in ('libio', 'libtonemap', 'include/dhdr/io', 'include/dhdr/tonemap'):
        for dirpath, _, names in os.walk(os.path.join(root, lib)):
            for f in names:
                path = os.path.join(dirpath, f)
                if not f.endswith(('.h', '.cpp')):
                    continue
                for inc in INCLUDE.findall(open(path, encoding='utf-8').read()):
                    if inc.startswith('dhdr/deferred/') or (
                            lib.endswith('io') and inc.startswith('dhdr/tonemap/')):
                        problems.append(f'{os.path.relpath(path, root)}: #include "{inc}" '
                                        'points up, out of its library')
    return layers, problems


def self_test(root):
    """Each damage to a copy of the tree must be reported."""
    layers = layer_order(root)
    low, high = layers[0], layers[-1]
    high_header = next(f for f, l in library_files(root)
                       if l == high and f.startswith('include/') and f.endswith('.h'))
    low_source = next(f for f, l in library_files(root) if l == low and f.endswith('.cpp'))
    cases = {
        'a wrong-way include': lambda t: append(t, low_source,
                                               '#include <' + high_header[len('include/'):] + '>\n'),
        'a file at the top': lambda t: append(t, 'libdeferred/src/stray.cpp', '\n'),
        'a folder that is no layer': lambda t: append(t, 'libdeferred/src/misc/stray.cpp', '\n'),
        'an include loop': lambda t: loop(t, low),
        'libio including libdeferred': lambda t: append(
            t, 'libio/src/stray.cpp', '#include <' + high_header[len('include/'):] + '>\n'),
    }
    failed = 0
    for name, damage in cases.items():
        with tempfile.TemporaryDirectory() as tmp:
            for part in ('libdeferred', 'include', 'libio', 'libtonemap', 'docs'):
                shutil.copytree(os.path.join(root, part), os.path.join(tmp, part))
            damage(tmp)
            _, problems = check(tmp)
            print(f'{"ok  " if problems else "MISSED"} {name}: {problems[:1]}')
            failed += not problems
    return failed


def append(tmp, rel, text):
    path = os.path.join(tmp, rel)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, 'a', encoding='utf-8') as f:
        f.write(text)


def loop(tmp, layer):
    append(tmp, f'libdeferred/src/{layer}/loop_a.h', f'#include "{layer}/loop_b.h"\n')
    append(tmp, f'libdeferred/src/{layer}/loop_b.cpp', f'#include "{layer}/loop_a.h"\n')
    append(tmp, f'libdeferred/src/{layer}/loop_b.h', '\n')
    append(tmp, f'libdeferred/src/{layer}/loop_a.cpp', f'#include "{layer}/loop_b.h"\n')


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    root = sys.argv[1]
    if sys.argv[2:] == ['--self-test']:
        failed = self_test(root)
        print(f'{5 - failed} passed, {failed} failed')
        return 1 if failed else 0
    layers, problems = check(root)
    for p in problems:
        print(p)
    print(f'libdeferred: {len(layers)} layers ({", ".join(layers)}); '
          f'{len(problems)} violation(s)')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
