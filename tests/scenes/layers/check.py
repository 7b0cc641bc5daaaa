"""The structure of src/ (the design card's style rules), checked on the source:
- folders are layers and `use` only points down, in the order
  core < linalg < laws < elements < mesh < contact < input < assembly < output < time < studies
  (a module may use its own folder and the folders below it; src/rebond.f90 is the top);
- one module per impact mode, none using another: impact_paper, impact_persist, impact_massless,
  impact_symmetric may use the shared impact_space, impact_groups, impact_scaling, impact_report
  and impact_kernels, never each other (changing one mode cannot change another);
- one module (or submodule) per file, files <= 900 lines, lines <= 132 characters.
"""
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

ORDER = ['core', 'linalg', 'laws', 'elements', 'mesh', 'contact', 'input', 'assembly', 'output', 'time', 'studies']
MODES = ['impact_paper', 'impact_persist', 'impact_massless', 'impact_symmetric']

files = sorted(glob.glob(os.path.join(sc.ROOT, 'src', '*', '*.f90')))
home = {}
text = {}
for f in files:
    rel = os.path.relpath(f, sc.ROOT)
    with open(f, encoding='utf-8') as h:
        text[rel] = h.read()
    for m in re.findall(r'^\s*module\s+(\w+)\s*$', text[rel], re.M | re.I):
        home[m.lower()] = rel

folders = sorted({r.split(os.sep)[1] for r in text})
sc.report('every folder of src/ has its layer (%s)' % ', '.join(folders), set(folders) <= set(ORDER),
          'unknown: %s' % sorted(set(folders) - set(ORDER)))

upward = []
crossing = []
for rel, t in text.items():
    d = rel.split(os.sep)[1]
    for m in re.findall(r'^\s*use\s+(\w+)', t, re.M | re.I):
        m = m.lower()
        if m not in home:
            continue                              # a library module (hdf5, mpi_f08, iso_c_binding)
        dm = home[m].split(os.sep)[1]
        if d in ORDER and dm in ORDER and ORDER.index(dm) > ORDER.index(d):
            upward.append('%s uses %s (%s)' % (rel, m, dm))
        me = os.path.splitext(os.path.basename(rel))[0]
        if me in MODES and m in MODES and m != me:
            crossing.append('%s uses %s' % (rel, m))
sc.report('use only points down (%d files)' % len(text), not upward, '; '.join(upward[:8]))
sc.report('no impact mode uses another (%s)' % ', '.join(MODES), not crossing, '; '.join(crossing))
missing = [m for m in MODES if m not in home]
sc.report('each impact mode has its own module', not missing, 'missing: %s' % missing)

many = [r for r, t in text.items()
        if len(re.findall(r'^\s*(?:module\s+(?!(?:procedure|subroutine|function|pure|elemental|recursive)\b)\w+\s*$|submodule\s*\()', t, re.M | re.I)) != 1]
sc.report('one module or submodule per file', not many, ', '.join(many))
long_files = ['%s (%d)' % (r, t.count('\n')) for r, t in text.items() if t.count('\n') > 900]
sc.report('files <= 900 lines', not long_files, ', '.join(long_files))
long_lines = ['%s:%d' % (r, i + 1) for r, t in text.items() for i, ln in enumerate(t.split('\n')) if len(ln) > 132]
sc.report('lines <= 132 characters', not long_lines, ', '.join(long_lines[:8]))
