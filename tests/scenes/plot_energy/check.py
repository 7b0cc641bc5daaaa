"""tools/plot_energy.py on the runs a user makes (issue 37, item 7): it draws a contact run that has
no probe (the contact forces of contacts.csv instead of exit 2), names the external work by its
sources (gravity potential, or the work of loads, pressure, imposed motion), labels a probe by its
kind and unit, draws bounces only where the body bounces, and shows the energy the contacts hold.
Each run writes a PNG; its figure text is read back from the SVG the same call can write.
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

TOOL = os.path.join(sc.ROOT, 'tools', 'plot_energy.py')


def plot(out, scene=None, extra=()):
    png = os.path.join(out, 'energy.svg')
    cmd = ['/usr/bin/python3', TOOL, out, '-o', png] + (['--scene', scene] if scene else []) + list(extra)
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=sc.ROOT)
    text = open(png).read() if p.returncode == 0 and os.path.exists(png) else ''
    return p.returncode, p.stdout + p.stderr, text


# A point mass on the ground, no gravity, no probe: contact forces instead of an error.
pm = sc.write_scene('pm.dat', 'NODE ball AT 0 0.01\nELEMENT pm TYPE MASS NODES ball\nSECTION m2 MASS 2\n'
                    'MODEL pm SECTION m2\nINITIAL ball VELOCITY 1 -1\nOBSTACLE ground NODES ball POINT 0 0 NORMAL 0 1\n'
                    'TIME STEP 1e-3 END 0.03\nOUTPUT HISTORY EVERY 1 FIELDS EVERY 0\n')
out = sc.run_ok(pm)
rc, msg, svg = plot(out, pm)
sc.report('a contact run without probes is drawn (exit 0)', rc == 0, msg.strip())
sc.report('... with the contact force of contacts.csv', 'contact forces' in svg)
sc.report('... and no bounce drawn (it bounces once)', 'no bounce to draw' in svg)

# Velocity probes: labelled velocity (m/s), no apexes drawn on them.
out = sc.run_ok(pm, ['OUTPUT.PROBE=ball VX ball VY'])
rc, msg, svg = plot(out, pm)
sc.report('velocity probes labelled "velocity (m/s)"', rc == 0 and 'velocity (m/s)' in svg, msg.strip())
sc.report('no apex on a velocity probe', '0 apexes' in msg, msg.strip())

# Gravity only: "gravity potential"; the bounces of mass_bounce drawn.
mb = os.path.join('inputs', 'mass_bounce.dat')
out = sc.run_ok(mb, ['TIME.END=5'])
rc, msg, svg = plot(out, mb)
sc.report('gravity alone: the external work is the gravity potential', rc == 0 and 'gravity potential' in svg, msg.strip())
sc.report('mass_bounce: its bounces drawn (apexes found)', 'rebound (apex) heights' in svg and ' 6 apexes' in msg,
          msg.strip())
sc.report('a displacement probe labelled "height above ground (m)"', 'height above ground (m)' in svg)

# A pressure and a load: the work named by both sources.
blk = sc.write_scene('blk.dat', 'RECTANGLE b ORIGIN 0 0 SIZE 0.2 0.05 ELEMENTS 4 2 TYPE QUAD4\n'
                     'MATERIAL alu ELASTIC YOUNG 7e10 POISSON 0.33 DENSITY 2700\nSECTION t THICKNESS 0.01\n'
                     'MODEL b MATERIAL alu SECTION t\nFIX b.left ALL\nPRESSURE b.top VALUE 1e5\n'
                     'LOAD tip NODES b.top_right FORCE 0 -10\nTIME STEP 1e-5 END 1e-3\n'
                     'OUTPUT HISTORY EVERY 1 FIELDS EVERY 0 PROBE b.top_right UY\n')
out = sc.run_ok(blk)
rc, msg, svg = plot(out, blk)
sc.report('pressure and a load: the work named by its sources', rc == 0 and 'work of pressure, loads' in svg, msg.strip())
sc.report('no contact: no apex, no bounce', '0 apexes' in msg and 'no bounce to draw' in svg, msg.strip())

# SYMMETRIC's held energy has its own curve.
bar = sc.write_scene('bar.dat', 'LINE bar FROM 0.002 0 TO 0.202 0 ELEMENTS 20 TYPE BAR2\n'
                     'MATERIAL steel ELASTIC YOUNG 2e11 POISSON 0 DENSITY 8000\nSECTION rod AREA 4e-4\n'
                     'MODEL bar MATERIAL steel SECTION rod MASS MIXED\nFIX bar UY\nINITIAL bar VELOCITY -100 0\n'
                     'OBSTACLE wall NODES bar.start POINT 0 0 NORMAL 1 0\nTIME STEP 2e-8 END 1.2e-4\n'
                     'SCHEME IMPACT SYMMETRIC\nOUTPUT HISTORY EVERY 20 FIELDS EVERY 0 PROBE bar.end UX\n')
out = sc.run_ok(bar)
rc, msg, svg = plot(out, bar)
sc.report('SYMMETRIC: the energy held by the contacts drawn', rc == 0 and 'held by contacts' in svg, msg.strip())
