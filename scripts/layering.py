#!/usr/bin/python3
"""scripts/layering.py - the arrows point down (STYLE.md rule 1; issue 26): every #include from a
module reaches the same module or one below it in the pipeline's order. Public headers
(include/hovox/X.h) belong to the module that implements them. Prints each include that points
up (file, line, the header and the two modules) and exits 1 when there is one.

usage: scripts/layering.py [ROOT]
"""
import os
import re
import sys

# low to high; a module may include only modules at its own position or before it
ORDER = [
    'src/core', 'volumes', 'src/image', 'src/mesh', 'src/io', 'WDG slicer', 'src/geometry', 'src/voxel', 'src/field',
    'src/material', 'src/colour', 'src/export', 'model formats', 'src/model', 'slicing', 'renderer',
    'src/plot', 'src/viewer', 'src/lua', 'src/cli', 'python/src',
]
# the geometry record (a model's leaves and Boolean tree) is data the voxelizer and the Booleans
# write, so it sits just above the formats that give its meshes;
# the formats wing holds mesh and volume formats (low: the store and the mesh below them) and
# model formats, which read and write whole graded models: 3MF Volumetric voxelizes through
# src/voxel and writes the export's property stacks, so it sits above them, below the one model
# loader (src/model) that picks a model reader by content; the shape's 3MF core package (issue 28)
# writes a model's materials the same way, so it sits there too
MODEL_FORMATS = ('src/io/3mf/volumetric_', 'src/io/3mf/shape_write')
# the WDG slicer (a mesh's closed outlines at a height; Wu 2.4.1) is what the geometry record's
# mesh leaves answer with, so it sits below it; the rest of slicing/ (resampling, halftoning, the
# stack writer) is above everything that makes models
WDG = ('slicing/wdg.c', 'slicing/slice_plan.c', 'slicing/contours.c', 'slicing/slice_internal.h')
# public headers and the module behind each
PUBLIC = {
    'core.h': 'src/core', 'options.h': 'src/core', 'volume.h': 'volumes', 'image.h': 'src/image',
    'mesh.h': 'src/mesh', 'generate.h': 'src/mesh', 'threemf.h': 'src/io', 'scan.h': 'src/io',
    'model.h': 'src/model', 'voxelize.h': 'src/voxel', 'field.h': 'src/field',
    'material.h': 'src/material', 'profile.h': 'src/material', 'colour.h': 'src/colour', 'lut.h': 'src/colour',
    'geometry.h': 'src/geometry', 'solid.h': 'src/geometry', 'export.h': 'src/export', 'slice.h': 'WDG slicer',
    'layers.h': 'slicing', 'tray.h': 'slicing', 'dist.h': 'slicing', 'render.h': 'renderer',
    'plot.h': 'src/plot', 'viewer.h': 'src/viewer', 'placement.h': 'src/mesh',
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def module_of(path):
    if path.startswith(MODEL_FORMATS):
        return 'model formats'
    if path in WDG:
        return 'WDG slicer'
    for m in sorted(ORDER, key=len, reverse=True):
        if path == m or path.startswith(m + '/'):
            return m
    if path.startswith('include/hovox/'):
        return PUBLIC.get(os.path.basename(path), '?')
    return None


def resolve(src, inc, root):
    for base in (os.path.dirname(src), 'src', '.', 'include'):
        q = os.path.normpath(os.path.join(base, inc))
        if os.path.exists(os.path.join(root, q)):
            return q
    return None


def readme_layout(root):
    """Where README.md's Layout table (layer | stage | folder | public headers) and this file
    disagree: a row's folder not at its layer, a public header in another module's row, a module
    or a public header in no row."""
    path = os.path.join(root, 'README.md')
    if not os.path.exists(path):
        return []
    m = re.search(r'^### Layout\n(.*?)(?=^#|\Z)', open(path, encoding='utf-8').read(), re.M | re.S)
    if not m:
        return ['README.md: no "### Layout" section (the map stage -> folder -> header)']
    problems, seen, listed = [], set(), set()
    for line in m.group(1).split('\n'):
        cells = [c.strip() for c in line.strip().strip('|').split('|')]
        if len(cells) != 4 or not cells[0].isdigit():
            continue
        layer, folder = int(cells[0]), cells[2].strip('`').rstrip('/')
        mod = module_of(folder)
        if mod in (None, '?'):
            problems.append(f'README.md Layout: layer {layer}: {folder} is no module of scripts/layering.py')
            continue
        seen.add(mod)
        if ORDER.index(mod) != layer:
            problems.append(f'README.md Layout: {folder} ({mod}) is at layer {layer}, '
                            f'scripts/layering.py has it at {ORDER.index(mod)}')
        for h in re.findall(r'`(\w+\.h)`', cells[3]):
            listed.add(h)
            if PUBLIC.get(h) != mod:
                problems.append(f'README.md Layout: layer {layer} lists {h}, which belongs to {PUBLIC.get(h, "no module")}')
    problems += [f'README.md Layout: no row for {mod}' for mod in ORDER if mod not in seen]
    problems += [f'README.md Layout: no row lists {h} ({mod})' for h, mod in sorted(PUBLIC.items()) if h not in listed]
    return problems


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else '.'
    bad = unknown = 0
    for p in readme_layout(root):
        print(p)
        bad += 1
    rank = {m: i for i, m in enumerate(ORDER)}
    files = []
    for top in [m for m in ORDER if m not in ('model formats', 'WDG slicer')] + ['include/hovox']:
        for d, _, names in os.walk(os.path.join(root, top)):
            files += [os.path.relpath(os.path.join(d, n), root) for n in names
                      if n.endswith(('.c', '.h', '.cpp', '.hpp', '.inc'))]
    for f in sorted(set(files)):
        me = module_of(f)
        if me == '?':
            print(f'{f}: a public header no module claims (add it to PUBLIC in scripts/layering.py)')
            unknown += 1
            continue
        text = open(os.path.join(root, f), errors='replace').read()
        for m in INCLUDE.finditer(text):
            q = resolve(f, m.group(1), root)
            if not q:
                continue
            them = module_of(q)
            if them in (None, '?') or them == me:
                continue
            if rank[them] > rank[me]:
                line = text.count('\n', 0, m.start()) + 1
                print(f'{f}:{line}: includes "{m.group(1)}" ({them}), above {me}')
                bad += 1
    print(f'layering: {bad} include(s) pointing up or README Layout rows out of step, {unknown} unclaimed header(s)')
    return 1 if bad or unknown else 0


if __name__ == '__main__':
    sys.exit(main())
