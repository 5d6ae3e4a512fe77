#!/usr/bin/env python3
"""The layering test: every #include "core/<folder>/..." must name a folder the including file may use.

Usage: check_layering.py SOURCE_DIR folder:dep,dep [folder:dep ...]
The folder:deps pairs come from core/CMakeLists.txt (shearbench_core_folder), so the build's link graph
and this check are one table. Also checked: core/ includes no VTK, ImGui or GLFW; widgets/ includes
nothing from app/; every .cpp/.hpp under core/ lives in a declared folder.
Prints file:line: what for each violation and exits 1, or prints a summary and exits 0.
"""
import pathlib
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]')
UI_HEADERS = re.compile(r'^(vtk|imgui|GLFW/|GL/|widgets/|app/)')


def parse_layers(args):
    allowed = {}
    for arg in args:
        folder, _, deps = arg.partition(':')
        allowed[folder] = {d for d in deps.split(',') if d} | {folder}
    return allowed


def includes(path):
    for n, line in enumerate(path.read_text(errors='replace').splitlines(), 1):
        m = INCLUDE.match(line)
        if m:
            yield n, m.group(1)


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    root = pathlib.Path(sys.argv[1])
    allowed = parse_layers(sys.argv[2:])
    errors, checked = [], 0
    for path in sorted((root / 'core').rglob('*')):
        if path.suffix not in ('.cpp', '.hpp'):
            continue
        rel = path.relative_to(root)
        folder = rel.parts[1] if len(rel.parts) == 3 else None
        if folder not in allowed:
            errors.append(f'{rel}:1: not in a declared core folder ({", ".join(sorted(allowed))})')
            continue
        checked += 1
        for n, inc in includes(path):
            if UI_HEADERS.match(inc):
                errors.append(f'{rel}:{n}: core/ must not include {inc}')
            m = re.match(r'core/([a-z_]+)/', inc)
            if inc.startswith('core/') and not m:
                errors.append(f'{rel}:{n}: {inc} is not in a core folder')
            elif m and m.group(1) not in allowed[folder]:
                errors.append(f'{rel}:{n}: core/{folder} may not include {inc} '
                              f'(core/{folder} may use: {", ".join(sorted(allowed[folder]))})')
    for path in sorted((root / 'widgets').rglob('*.[ch]pp')):
        for n, inc in includes(path):
            if inc.startswith('app/'):
                errors.append(f'{path.relative_to(root)}:{n}: widgets/ must not include {inc}')
    for e in errors:
        print(e)
    if errors:
        print(f'layering: {len(errors)} violation(s)')
        return 1
    print(f'layering: {checked} core files in {len(allowed)} folders, every include goes down')
    return 0


if __name__ == '__main__':
    sys.exit(main())
