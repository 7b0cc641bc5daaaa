"""Names with commas and quotes in the result files (issue 37, items 4 and 10): a group, probe or
contact name enters probes.csv, contacts.csv and events.csv as one CSV field (RFC 4180: between
double quotes), so that every row keeps its columns and a CSV reader gives the
name back as written. Before, a comma in a Gmsh physical name or an OBSTACLE name shifted the
columns of probes.csv and contacts.csv.
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

SCENE = sc.write_scene('names.dat', '''TITLE "a mass on a spring, dropped on a wall"
NODE a AT 0 0.01
ELEMENT m TYPE MASS NODES a
SECTION pm MASS 2
MODEL m SECTION pm
GROUP "ball, left" NODES a
INITIAL a VELOCITY 0 -1
OBSTACLE "wall, north" NODES "ball, left" POINT 0 0 NORMAL 0 1
TIME STEP 1e-3 END 0.03
OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE "ball, left" UY
''')
out = sc.run_ok(SCENE)


def rows(name):
    with open(os.path.join(out, name), newline='') as f:
        return list(csv.reader(f))


p = rows('probes.csv')
sc.report('probes.csv: the header names the probe "ball, left.UY" as one field', p[0] == ['step', 'time', 'ball, left.UY'],
          repr(p[0]))
sc.report('probes.csv: every row has the header\'s columns', all(len(r) == len(p[0]) for r in p), '')
c = rows('contacts.csv')
sc.report('contacts.csv: every row has the header\'s columns (14)', len(c[0]) == 14 and all(len(r) == 14 for r in c),
          repr(c[:2]))
sc.report('contacts.csv: the contact name read back whole', all(r[2] == 'wall, north' for r in c[1:]), repr(c[1][2]))
e = rows('events.csv')
sc.report('events.csv: an impact, the contact name read back whole, columns kept',
          len(e) > 1 and all(len(r) == len(e[0]) for r in e) and e[1][-1] == 'wall, north', repr(e[:2]))
