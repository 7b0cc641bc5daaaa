"""Bad input is refused before anything is written.

Each case writes a small scene (a valid base scene with one defect) into a temporary directory and
runs bin/rebond on it with -o pointing to a directory that does not exist. For every case:
exit status 2, stderr names "<file>:<line>:" with the line of the defect, the statement's keyword
and the word at fault (docs/input.md, "Errors name the file and line, the statement, and the word
at fault"), and the output directory was not created. Command-line errors (--set) name the
option and the word instead of a line. A zero density is legitimate and must run.
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

BASE = [
    'TITLE "spring and mass"',                 # 1
    'NODE a AT 0 0',                           # 2
    'NODE b AT 1 0',                           # 3
    'ELEMENT s TYPE SPRING NODES a b',         # 4
    'ELEMENT m TYPE MASS NODES b',             # 5
    'MATERIAL k ELASTIC YOUNG 8',              # 6
    'SECTION pm MASS 2',                       # 7
    'MODEL s MATERIAL k',                      # 8
    'MODEL m SECTION pm',                      # 9
    'FIX a ALL',                               # 10
    'FIX b UY',                                # 11
    'INITIAL b DISPLACEMENT 0.1 0',            # 12
    'TIME STEP 0.01 END 0.1',                  # 13
    'OUTPUT PROBE b UX',                       # 14
]

BLOCKS = [                                     # two blocks, 7 and 4 elements along the contact
    'RECTANGLE lo ORIGIN 0 0 SIZE 1 0.2 ELEMENTS 7 1 TYPE QUAD4',
    'RECTANGLE up ORIGIN 0 0.21 SIZE 1 0.2 ELEMENTS 4 1 TYPE QUAD4',
    'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
    'SECTION sl THICKNESS 0.1',
    'MODEL lo MATERIAL st SECTION sl',
    'MODEL up MATERIAL st SECTION sl',
    'FIX lo.bottom ALL',
    'INITIAL up VELOCITY 0 -1',
    'TIME STEP 1e-5 END 1e-3',
]

QUAD = [
    'NODE p1 AT 0 0',
    'NODE p2 AT 1 0',
    'NODE p3 AT 1 1',
    'NODE p4 AT 0 1',
    'ELEMENT q TYPE QUAD4 NODES p1 p4 p3 p2',  # 5: clockwise
    'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
    'SECTION sl THICKNESS 0.1',
    'MODEL q MATERIAL st SECTION sl',          # 8
    'FIX p1 ALL',
    'FIX p4 ALL',
    'TIME STEP 1e-4 END 1e-3',
]

BAR = [                                        # a bar; its MODEL is line 5, then TIME
    'LINE bar FROM 0 0 TO 1 0 ELEMENTS 4 TYPE BAR2',
    'FIX bar UY',
    'MATERIAL m ELASTIC YOUNG 1 DENSITY 1',
    'SECTION s AREA 1',
]

BROKEN_MSH = """$MeshFormat
4.1 0 8
$EndMeshFormat
$Nodes
1 2 1 2
0 1 0 2
1
2
0 0 0
1 x 0
$EndNodes
"""                                            # line 10: "1 x 0", a coordinate that is not a number


def edit(lines, lineno, new):
    """Replace line `lineno` (1-based) by the lines of `new` (a string, or None to delete)."""
    out = list(lines)
    out[lineno - 1:lineno] = [] if new is None else new.split('\n')
    return out


def write(name, lines, extra=None):
    d = os.path.join(sc.TMP, 'scenes')
    os.makedirs(d, exist_ok=True)
    path = os.path.join(d, name + '.dat')
    with open(path, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    for fname, text in (extra or {}).items():
        with open(os.path.join(d, fname), 'w') as f:
            f.write(text)
    return path


# name, scene lines, extra files, --set arguments, expected line (None: command-line error),
# keyword, the word at fault as the message must show it (quoted, "at 'word'", as in docs/input.md;
# a missing parameter is named in the text instead)
CASES = [
    ('unknown keyword', edit(BASE, 6, 'MATERIEL k ELASTIC YOUNG 8'), None, [], 6, 'MATERIEL', 'MATERIEL'),
    ('unknown parameter', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG 8 POISON 0.3'), None, [], 6, 'MATERIAL', 'POISON'),
    ('missing STEP in TIME', edit(BASE, 13, 'TIME END 0.1'), None, [], 13, 'TIME', 'missing parameter STEP'),
    ('repeated parameter', edit(BASE, 13, 'TIME STEP 0.01 END 0.1 STEP 0.02'), None, [], 13, 'TIME', 'STEP'),
    ('malformed number', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG 2.1e1x'), None, [], 6, 'MATERIAL', '2.1e1x'),
    ('negative density', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG 8 DENSITY -7800'), None, [], 6, 'MATERIAL', '-7800'),
    ('zero YOUNG', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG 0'), None, [], 6, 'MATERIAL', '0'),
    ('negative YOUNG', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG -2.1e11'), None, [], 6, 'MATERIAL', '-2.1e11'),
    ('zero TIME STEP', edit(BASE, 13, 'TIME STEP 0 END 0.1'), None, [], 13, 'TIME', '0'),
    ('negative TIME STEP', edit(BASE, 13, 'TIME STEP -1e-3 END 0.1'), None, [], 13, 'TIME', '-1e-3'),
    ('unknown group in FIX', edit(BASE, 10, 'FIX nowhere ALL'), None, [], 10, 'FIX', 'nowhere'),
    ('unknown group in MODEL', edit(BASE, 8, 'MODEL ss MATERIAL k'), None, [], 8, 'MODEL', 'ss'),
    ('unknown group in PROBE', edit(BASE, 14, 'OUTPUT PROBE c UX'), None, [], 14, 'OUTPUT', 'c'),
    ('zero-length LINE', BASE + ['LINE bar FROM 1 1 TO 1 1 ELEMENTS 4 TYPE BAR2'], None, [], 15, 'LINE bar', 'TO'),
    ('BAR2 on coincident nodes',
     BASE + ['NODE c AT 1 0', 'ELEMENT bb TYPE BAR2 NODES b c', 'SECTION tube AREA 1e-4',
             'MODEL bb MATERIAL k SECTION tube'], None, [], 18, 'MODEL', 'bb'),
    ('clockwise QUAD4', QUAD, None, [], 8, 'MODEL', 'q'),
    ('missing .msh file', edit(BASE, 14, 'GMSH g FILE nothere.msh'), None, [], 14, 'GMSH', 'nothere.msh'),
    ('malformed .msh file', edit(BASE, 14, 'GMSH g FILE broken.msh'), {'broken.msh': BROKEN_MSH}, [], 14, 'GMSH',
     'broken.msh'),
    ('repeated TIME statement', BASE + ['TIME STEP 0.02 END 0.2'], None, [], 15, 'TIME', 'TIME'),
    ('unterminated quote', edit(BASE, 1, 'TITLE "spring and mass'), None, [], 1, 'TITLE', '"spring and mass'),
    ('unknown MULTIPLIERS choice', BASE + ['SCHEME MULTIPLIERS DENSE'], None, [], 15, 'SCHEME', 'DENSE'),
    ('negative AUGMENTED_ABOVE', BASE + ['SCHEME AUGMENTED_ABOVE -3'], None, [], 15, 'SCHEME', '-3'),
    ('SCHEME ZONE not AUTO, ON or OFF', BASE + ['SCHEME ZONE SOMETIMES'], None, [], 15, 'SCHEME', 'SOMETIMES'),
    ('unknown SOLVER library', BASE + ['SCHEME SOLVER PARDISO'], None, [], 15, 'SCHEME', 'PARDISO'),
    ('OUT_OF_CORE without MUMPS', BASE + ['SCHEME SOLVER CHOLMOD OUT_OF_CORE'], None, [], 15, 'SCHEME', 'OUT_OF_CORE'),
    ('a word after SOLVER MUMPS that is not OUT_OF_CORE', BASE + ['SCHEME SOLVER MUMPS FAST'], None, [], 15, 'SCHEME',
     'FAST'),
    ('continuation at end of file', edit(BASE, 14, 'OUTPUT PROBE b UX &'), None, [], 14, 'OUTPUT', '&'),
    ('initial displacement inside an obstacle', BASE + ['OBSTACLE wall NODES b POINT 1.05 0 NORMAL -1 0'], None, [],
     15, 'OBSTACLE wall', 'wall'),
    ('RESTITUTION above 1', BASE + ['OBSTACLE wall NODES b POINT 2 0 NORMAL -1 0 RESTITUTION 1.5'], None, [], 15,
     'OBSTACLE wall', '1.5'),
    ('negative RESTITUTION', BASE + ['GAP g PAIRS a b RESTITUTION -0.1'], None, [], 15, 'GAP g', '-0.1'),
    ('MASSLESS on a point mass', BASE + ['OBSTACLE wall NODES b POINT 2 0 NORMAL -1 0', 'SCHEME IMPACT MASSLESS'], None,
     [], 15, 'OBSTACLE wall', 'wall'),
    ('a mixing factor after LUMPED', edit(QUAD, 8, QUAD[7] + ' MASS LUMPED 0.5'), None, [], 8, 'MODEL', '0.5'),
    ('a mixing factor that is not a number', edit(QUAD, 8, QUAD[7] + ' MASS MIXED half'), None, [], 8, 'MODEL', 'half'),
    ('MASS MIXED above 1 on a QUAD4', edit(QUAD, 8, QUAD[7] + ' MASS MIXED 1.1'), None, [], 8, 'MODEL', '1.1'),
    ('MASS MIXED at 1.5 on a BAR2 (singular element mass)', BAR + ['MODEL bar MATERIAL m SECTION s MASS MIXED 1.5',
                                                                'TIME STEP 0.1 END 1'],
     None, [], 5, 'MODEL', '1.5'),
    ('negative MASS MIXED', BAR + ['MODEL bar MATERIAL m SECTION s MASS MIXED -0.1',
                                   'TIME STEP 0.1 END 1'], None, [], 5, 'MODEL', '-0.1'),
    ('MASS TUNED on a QUAD4', edit(QUAD, 8, QUAD[7] + ' MASS TUNED'), None, [], 8, 'MODEL', 'TUNED'),
    ('a mixing factor after TUNED', BAR + ['MODEL bar MATERIAL m SECTION s MASS TUNED 0.7', 'TIME STEP 0.1 END 1'], None,
     [], 5, 'MODEL', '0.7'),
    ('MASS TUNED past c h over dx = 1', BAR + ['MODEL bar MATERIAL m SECTION s MASS TUNED', 'TIME STEP 0.3 END 1'], None, [],
     5, 'MODEL bar', 'TUNED'),
    ('KINEMATICS LARGE on a MASS', edit(BASE, 9, BASE[8] + ' KINEMATICS LARGE'), None, [], 9, 'MODEL', 'LARGE'),
    ('KINEMATICS LARGE with DAMPING BETA', edit(BASE, 8, BASE[7] + ' KINEMATICS LARGE DAMPING BETA 1e-4'), None, [], 8,
     'MODEL', 'BETA'),
    ('KINEMATICS LARGE with INITIAL STATIC', edit(BASE, 8, BASE[7] + ' KINEMATICS LARGE') + ['INITIAL b STATIC FORCE 1 0'], None,
     [], 15, 'INITIAL', 'STATIC'),
    ('unknown KINEMATICS', edit(BASE, 8, BASE[7] + ' KINEMATICS HUGE'), None, [], 8, 'MODEL', 'HUGE'),
    ('HYPERELASTIC without KINEMATICS LARGE', edit(QUAD, 5, 'ELEMENT q TYPE QUAD4 NODES p1 p2 p3 p4')[:5] +
     ['MATERIAL rub HYPERELASTIC YOUNG 1e7 POISSON 0.45 DENSITY 1000', 'SECTION sl THICKNESS 0.1',
      'MODEL q MATERIAL rub SECTION sl'] + QUAD[8:], None, [], 8, 'MODEL q', 'rub'),
    ('STRAIN_MEASURE LOG without KINEMATICS LARGE', edit(QUAD, 5, 'ELEMENT q TYPE QUAD4 NODES p1 p2 p3 p4')[:7] +
     ['MODEL q MATERIAL st SECTION sl STRAIN_MEASURE LOG'] + QUAD[8:], None, [], 8, 'MODEL', 'LOG'),
    ('STRAIN on a SPRING', edit(BASE, 8, BASE[7] + ' KINEMATICS LARGE STRAIN_MEASURE LOG'), None, [], 8, 'MODEL', 'LOG'),
    ('unknown STRAIN', edit(QUAD, 5, 'ELEMENT q TYPE QUAD4 NODES p1 p2 p3 p4')[:7] +
     ['MODEL q MATERIAL st SECTION sl KINEMATICS LARGE STRAIN_MEASURE HENCKY'] + QUAD[8:], None, [], 8, 'MODEL', 'HENCKY'),
    ('STRAIN_MEASURE LOG with HYPERELASTIC', edit(QUAD, 5, 'ELEMENT q TYPE QUAD4 NODES p1 p2 p3 p4')[:5] +
     ['MATERIAL rub HYPERELASTIC YOUNG 1e7 POISSON 0.45 DENSITY 1000', 'SECTION sl THICKNESS 0.1',
      'MODEL q MATERIAL rub SECTION sl KINEMATICS LARGE STRAIN_MEASURE LOG'] + QUAD[8:], None, [], 8, 'MODEL', 'LOG'),
    ('HYPERELASTIC on a SPRING', edit(BASE, 6, 'MATERIAL k HYPERELASTIC YOUNG 8'), None, [], 8, 'MODEL', 'k'),
    ('FORMULATION BBAR in plane stress', edit(QUAD, 5, 'ELEMENT q TYPE QUAD4 NODES p1 p2 p3 p4')[:7] +
     ['MODEL q MATERIAL st SECTION sl PLANE STRESS FORMULATION BBAR'] + QUAD[8:], None, [], 8, 'MODEL', 'BBAR'),
    ('FORMULATION BBAR on a TRI3', ['NODE p1 AT 0 0', 'NODE p2 AT 1 0', 'NODE p3 AT 1 1', 'ELEMENT t TYPE TRI3 NODES p1 p2 p3',
                                    'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800', 'SECTION sl THICKNESS 0.1',
                                    'MODEL t MATERIAL st SECTION sl FORMULATION BBAR', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 7, 'MODEL', 'BBAR'),
    ('FORMULATION BBAR on a SPRING', edit(BASE, 8, BASE[7] + ' FORMULATION BBAR'), None, [], 8, 'MODEL', 'BBAR'),
    # Issue 32, item 3: AXISYMMETRIC models (x = r >= 0, y the axis).
    ('AXISYMMETRIC with a node at r < 0', ['RECTANGLE c ORIGIN -0.1 0 SIZE 1 1 ELEMENTS 2 2 TYPE QUAD4',
                                           'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
                                           'MODEL c MATERIAL st AXISYMMETRIC', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 3, 'MODEL', 'AXISYMMETRIC'),
    ('AXISYMMETRIC with PLANE', ['RECTANGLE c ORIGIN 0 0 SIZE 1 1 ELEMENTS 2 2 TYPE QUAD4',
                                 'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
                                 'MODEL c MATERIAL st AXISYMMETRIC PLANE STRAIN', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 3, 'MODEL', 'PLANE'),
    ('AXISYMMETRIC with a THICKNESS', ['RECTANGLE c ORIGIN 0 0 SIZE 1 1 ELEMENTS 2 2 TYPE TRI6',
                                       'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800', 'SECTION sl THICKNESS 0.1',
                                       'MODEL c MATERIAL st SECTION sl AXISYMMETRIC', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 4, 'MODEL', 'sl'),
    ('AXISYMMETRIC on a BAR2', BAR + ['MODEL bar MATERIAL m SECTION s AXISYMMETRIC', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 5, 'MODEL', 'AXISYMMETRIC'),
    ('a BAR2 in an axisymmetric scene', ['RECTANGLE c ORIGIN 0 0 SIZE 1 1 ELEMENTS 2 2 TYPE QUAD4',
                                         'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800', 'MODEL c MATERIAL st AXISYMMETRIC',
                                         'LINE bar FROM 2 0 TO 3 0 ELEMENTS 2 TYPE BAR2', 'SECTION s AREA 1',
                                         'MODEL bar MATERIAL st SECTION s', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 6, 'MODEL', 'bar'),
    ('axisymmetric and planar surface models', ['RECTANGLE c ORIGIN 0 0 SIZE 1 1 ELEMENTS 2 2 TYPE QUAD4',
                                                'RECTANGLE d ORIGIN 2 0 SIZE 1 1 ELEMENTS 2 2 TYPE QUAD4',
                                                'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
                                                'MODEL c MATERIAL st AXISYMMETRIC', 'MODEL d MATERIAL st',
                                                'TIME STEP 1e-4 END 1e-3'],
     None, [], 5, 'MODEL', 'd'),
    ('HYPERELASTIC with AXISYMMETRIC LARGE', ['RECTANGLE c ORIGIN 0 0 SIZE 1 1 ELEMENTS 2 2 TYPE QUAD4',
                                              'MATERIAL r HYPERELASTIC YOUNG 1e7 POISSON 0.45 DENSITY 1000',
                                              'MODEL c MATERIAL r AXISYMMETRIC KINEMATICS LARGE', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 3, 'MODEL', 'AXISYMMETRIC'),
    ('a following PRESSURE on an axisymmetric LARGE model', ['RECTANGLE c ORIGIN 0 0 SIZE 1 1 ELEMENTS 2 2 TYPE QUAD4',
                                                             'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
                                                             'MODEL c MATERIAL st AXISYMMETRIC KINEMATICS LARGE',
                                                             'PRESSURE c.right VALUE 1e6', 'TIME STEP 1e-4 END 1e-3'],
     None, [], 4, 'PRESSURE', 'c.right'),
    # Issue 35, item 4: GROUP by geometry and operation.
    ('an empty GROUP BOX', BASE + ['GROUP far NODES BOX 5 5 6 6'], None, [], 15, 'GROUP', 'far'),
    ('RADIUS without SPHERE', BASE + ['GROUP g NODES BOX 0 0 1 1 RADIUS 2'], None, [], 15, 'GROUP', 'RADIUS'),
    ('SPHERE without RADIUS', BASE + ['GROUP g NODES SPHERE 0 0'], None, [], 15, 'GROUP', 'SPHERE'),
    ('two selectors in a GROUP', BASE + ['GROUP g NODES BOX 0 0 1 1 SPHERE 0 0 RADIUS 1'], None, [], 15, 'GROUP',
     'SPHERE'),
    ('a zero NORMAL in GROUP PLANE', BASE + ['GROUP g NODES PLANE 0 0 NORMAL 0 0 TOLERANCE 0'], None, [], 15, 'GROUP',
     'NORMAL'),
    ('an inverted GROUP BOX', BASE + ['GROUP g NODES BOX 1 1 0 0'], None, [], 15, 'GROUP', 'BOX'),
    ('GROUP BOX OF an unknown group', BASE + ['GROUP g NODES BOX 0 0 1 1 OF nowhere'], None, [], 15, 'GROUP', 'nowhere'),
    ('GROUP names and a selector', BASE + ['GROUP g NODES a BOX 0 0 1 1'], None, [], 15, 'GROUP', 'a'),
    ('GROUP INTERSECTION of an unknown group', BASE + ['GROUP g NODES INTERSECTION a nowhere'], None, [], 15, 'GROUP',
     'nowhere'),
    # Issue 35, item 3: FUNCTION kinds.
    ('SINE with FREQUENCY 0', BASE + ['FUNCTION w SINE AMPLITUDE 1 FREQUENCY 0'], None, [], 15, 'FUNCTION', '0'),
    ('SINE without FREQUENCY', BASE + ['FUNCTION w SINE AMPLITUDE 1'], None, [], 15, 'FUNCTION',
     'missing parameter FREQUENCY'),
    ('two kinds of FUNCTION', BASE + ['FUNCTION w SINE AMPLITUDE 1 FREQUENCY 2 POINTS 0 0 1 1'], None, [], 15,
     'FUNCTION', 'SINE'),
    ('PHASE on a SMOOTH_STEP', BASE + ['FUNCTION w SMOOTH_STEP T 1 PHASE 30'], None, [], 15, 'FUNCTION', 'PHASE'),
    ('SMOOTH_STEP ending before its START', BASE + ['FUNCTION w SMOOTH_STEP T 1 START 2'], None, [], 15, 'FUNCTION',
     '1'),
    ('TABLE FILE missing', BASE + ['FUNCTION w TABLE FILE nothere.csv'], None, [], 15, 'FUNCTION', 'nothere.csv'),
    ('TABLE FILE not monotone', BASE + ['FUNCTION w TABLE FILE back.csv'], {'back.csv': 't,f\n0,0\n1,1\n0.5,2\n'}, [],
     15, 'FUNCTION', 'back.csv'),
    ('FILE on POINTS', BASE + ['FUNCTION w POINTS 0 0 1 1 FILE x.csv'], None, [], 15, 'FUNCTION', 'FILE'),
    # Issue 35, item 1: MODES.
    ('MODES 0', BASE + ['MODES 0'], None, [], 15, 'MODES', '0'),
    ('MODES not a number', BASE + ['MODES few'], None, [], 15, 'MODES', 'few'),
    ('MODES ABOVE negative', BASE + ['MODES 1 ABOVE -5'], None, [], 15, 'MODES', '-5'),
    ('MODES more than the equations', BASE + ['MODES 2'], None, [], 15, 'MODES', '2'),
    ('TIME END = START without MODES', edit(BASE, 13, 'TIME STEP 0.01 END 0'), None, [], 13, 'TIME', 'END'),
    ('unknown FORMULATION', edit(QUAD, 5, 'ELEMENT q TYPE QUAD4 NODES p1 p2 p3 p4')[:7] +
     ['MODEL q MATERIAL st SECTION sl FORMULATION FBAR'] + QUAD[8:], None, [], 8, 'MODEL', 'FBAR'),
    ('SUBSTEPS EXACT on a law without a potential', edit(edit(BASE, 6, 'MATERIAL k ELASTOPLASTIC YOUNG 8 YIELD 0.1'), 8,
     'MODEL s MATERIAL k SUBSTEPS EXACT'), None, [], 8, 'MODEL', 'EXACT'),
    ('DENSITY beyond 1e100', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG 8 DENSITY 1.7976931348623157e308'),
     None, [], 6, 'MATERIAL k', '1.7976931348623157e308'),
    ('YOUNG beyond 1e100', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG 1e300'), None, [], 6, 'MATERIAL k', '1e300'),
    ('two laws on one MATERIAL', edit(BASE, 6, 'MATERIAL k ELASTIC HYPERELASTIC YOUNG 8'), None, [], 6, 'MATERIAL', 'k'),
    ('MASSLESS with RESTITUTION below 1', BASE + ['OBSTACLE wall NODES b POINT 2 0 NORMAL -1 0 RESTITUTION 0.5',
                                                  'SCHEME IMPACT MASSLESS'], None, [], 15, 'OBSTACLE wall', 'RESTITUTION'),
    ('SYMMETRIC with RESTITUTION below 1', BASE + ['OBSTACLE wall NODES b POINT 2 0 NORMAL -1 0 RESTITUTION 0.5',
                                                   'SCHEME IMPACT SYMMETRIC'], None, [], 15, 'OBSTACLE wall', 'RESTITUTION'),
    ('GAP on coincident nodes without NORMAL', BASE + ['NODE c AT 1 0', 'ELEMENT mc TYPE MASS NODES c', 'MODEL mc SECTION pm',
                                                       'GAP g NODES b WITH c'], None, [], 18, 'GAP g', 'g'),
    # Issue 37: a contact or load node that carries no element of any MODEL (it would be a fixed
    # point), an INITIAL given twice for a node, an unknown group listing the existing ones.
    ('GAP on a node of no MODEL', BASE + ['NODE c AT 1.5 0', 'GAP g NODES b WITH c NORMAL 1 0'], None, [], 16, 'GAP g',
     'c'),
    ('GAP PAIRS on a node of no MODEL', BASE + ['NODE c AT 1.5 0', 'GAP g PAIRS b c'], None, [], 16, 'GAP g', 'c'),
    ('OBSTACLE on a node of no MODEL', BASE + ['NODE c AT 1.5 0', 'OBSTACLE w NODES c POINT 2 0 NORMAL -1 0'], None, [],
     16, 'OBSTACLE w', 'c'),
    ('GAP SEGMENTS on a block of no MODEL', edit(BLOCKS, 6, None) + ['GAP g NODES lo.top SEGMENTS up.bottom'], None, [],
     9, 'GAP g', 'up.bottom'),
    ('LOAD on a node of no MODEL', BASE + ['NODE c AT 1.5 0', 'LOAD f NODES c FORCE 1 0'], None, [], 16, 'LOAD f', 'c'),
    ('LOAD before the MODEL statements, on a node of no MODEL', ['NODE c AT 1.5 0', 'LOAD f NODES c FORCE 1 0'] + BASE,
     None, [], 2, 'LOAD f', 'c'),
    ('PRESSURE on a block of no MODEL', edit(BLOCKS, 6, None) + ['PRESSURE up.top VALUE 1e5'], None, [], 9,
     'PRESSURE', 'up.top'),
    ('INITIAL VELOCITY twice on a group', BASE + ['INITIAL b VELOCITY 1 0', 'INITIAL b VELOCITY 2 0'], None, [], 16,
     'INITIAL', 'b'),
    ('INITIAL DISPLACEMENT twice on a node (two groups)', BASE + ['GROUP ab NODES a b', 'INITIAL ab DISPLACEMENT 0.2 0'],
     None, [], 16, 'INITIAL', 'ab'),
    ('unknown node group lists the groups, closest first', BASE + ['LOAD f NODES bb FORCE 1 0'], None, [], 15, 'LOAD f',
     "existing groups: b, a"),
    ('GAP on non-matching meshes, ga finer', BLOCKS + ['GAP g NODES lo.top WITH up.bottom NORMAL 0 1'], None, [], 10,
     'GAP g', 'up.bottom'),
    ('GAP on non-matching meshes, gb finer', BLOCKS + ['GAP g NODES up.bottom WITH lo.top'], None, [], 10, 'GAP g',
     'lo.top'),
    ('GAP SEGMENTS with a node on no segment', BLOCKS + ['GROUP s NODES lo.top up.top_left',
                                                        'GAP g NODES up.bottom SEGMENTS s'], None, [], 11, 'GAP g', 's'),
    ('GAP SEGMENTS not a chain', BLOCKS + ['NODE s0 AT 2 0', 'NODE s1 AT 3 0', 'NODE s2 AT 2 1', 'NODE s3 AT 1.5 -1',
                                           'ELEMENT sp TYPE BAR2 NODES s0 s1 s0 s2 s0 s3', 'GROUP star NODES s0 s1 s2 s3',
                                           'GAP g NODES up.bottom SEGMENTS star'], None, [], 16, 'GAP g', 'star'),
    ('GAP SEGMENTS: a node starting on a BAR2 segment (gap 0)',
     ['LINE wall FROM 0 0 TO 1 0 ELEMENTS 2 TYPE BAR2', 'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
      'SECTION a AREA 1e-4', 'MODEL wall MATERIAL st SECTION a', 'FIX wall ALL', 'NODE ball AT 0.3 0',
      'ELEMENT pm TYPE MASS NODES ball', 'SECTION m MASS 1', 'MODEL pm SECTION m', 'INITIAL ball VELOCITY 0 -1',
      'GAP g NODES ball SEGMENTS wall', 'TIME STEP 1e-4 END 1e-3'], None, [], 11, 'GAP g', 'wall'),
    ('GAP SEGMENTS self-contact at rest', edit(BLOCKS, 2, 'RECTANGLE up ORIGIN 0 0.2 SIZE 1 0.2 ELEMENTS 4 1 TYPE QUAD4')
     + ['GROUP surf NODES lo.top up.bottom', 'GAP g NODES surf SEGMENTS surf'], None, [], 11, 'GAP g', 'surf'),
    ('GAP SEGMENTS with WITH', BLOCKS + ['GAP g NODES up.bottom SEGMENTS lo.top WITH lo.top'], None, [], 10, 'GAP g',
     'SEGMENTS'),
    ('GAP SEGMENTS facing nothing', BLOCKS + ['GAP g NODES up.top SEGMENTS lo.left'], None, [], 10, 'GAP g', 'lo.left'),
    ('GAP SEGMENTS following a LARGE model with MULTIPLIERS AUGMENTED',
     edit(BLOCKS, 6, 'MODEL up MATERIAL st SECTION sl KINEMATICS LARGE') + ['SCHEME MULTIPLIERS AUGMENTED',
                                                                          'GAP g NODES up.bottom SEGMENTS lo.top'],
     None, [], 11, 'GAP g', 'SEGMENTS'),
    ('GAP SEGMENTS following a LARGE model with IMPACT MASSLESS',
     edit(BLOCKS, 6, 'MODEL up MATERIAL st SECTION sl KINEMATICS LARGE') + ['SCHEME IMPACT MASSLESS',
                                                                          'GAP g NODES up.bottom SEGMENTS lo.top'],
     None, [], 11, 'GAP g', 'SEGMENTS'),
    ('GAP PAIRING without SEGMENTS', BLOCKS + ['GAP g NODES up.bottom WITH lo.top PAIRING STEP'], None, [], 10,
     'GAP g', 'PAIRING'),
    ('GAP SEGMENTS PAIRING not a choice', BLOCKS + ['GAP g NODES up.bottom SEGMENTS lo.top PAIRING ALWAYS'], None, [],
     10, 'GAP g', 'ALWAYS'),
    ('GAP SEGMENTS PAIRING STEP with IMPACT MASSLESS', BLOCKS + ['SCHEME IMPACT MASSLESS',
                                                                'GAP g NODES up.bottom SEGMENTS lo.top PAIRING STEP'],
     None, [], 11, 'GAP g', 'SEGMENTS'),
    ('GAP SEGMENTS PAIRING STEP with IMPACT SYMMETRIC', BLOCKS + ['SCHEME IMPACT SYMMETRIC',
                                                                 'GAP g NODES up.bottom SEGMENTS lo.top PAIRING STEP'],
     None, [], 11, 'GAP g', 'SEGMENTS'),
    ('GAP SEGMENTS self-contact of a LARGE beam (PAIRING STEP)',
     ['LINE s FROM 0 0 TO 1 0 ELEMENTS 4 TYPE BEAM2', 'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800',
      'SECTION b AREA 1e-4 INERTIA 1e-8', 'MODEL s MATERIAL st SECTION b KINEMATICS LARGE', 'TIME STEP 1e-3 END 1e-2',
      'GAP g NODES s SEGMENTS s'], None, [], 6, 'GAP g', 's'),
    ('GAP SEGMENTS RESTITUTION above 1', BLOCKS + ['GAP g NODES up.bottom SEGMENTS lo.top RESTITUTION 1.5'], None, [],
     10, 'GAP g', '1.5'),
    ('PRESSURE on a node', BLOCKS + ['PRESSURE lo.top_left VALUE 1e5'], None, [], 10, 'PRESSURE lo.top_left',
     'lo.top_left'),
    ('PRESSURE on a line of nodes inside the body', edit(BLOCKS, 1, 'RECTANGLE lo ORIGIN 0 0 SIZE 1 0.2 ELEMENTS 7 2 '
                                                       'TYPE QUAD4\nLINE cut FROM 0 0.1 TO 1 0.1 ELEMENTS 1 TYPE BAR2')
     + ['PRESSURE cut VALUE 1e5'], None, [], 11, 'PRESSURE cut', 'cut'),
    ('PRESSURE without VALUE', BLOCKS + ['PRESSURE lo.top'], None, [], 10, 'PRESSURE lo.top', 'lo.top'),
    ('TRACTION with one value', BLOCKS + ['TRACTION lo.top VALUE 1e5'], None, [], 10, 'TRACTION', 'VALUE'),
    ('PRESSURE DEAD with a value', BLOCKS + ['PRESSURE lo.top VALUE 1e5 DEAD 1'], None, [], 10, 'PRESSURE', '1'),
    ('TRACTION DEAD (a traction keeps its direction anyway)', BLOCKS + ['TRACTION lo.top VALUE 1e5 0 DEAD'], None, [],
     10, 'TRACTION', 'DEAD'),
    ('PRESSURE with an unknown function', BLOCKS + ['PRESSURE lo.top VALUE 1 FUNCTION nope'], None, [], 10,
     'PRESSURE lo.top', 'nope'),
    ('IMPOSE on a fixed DOF', BASE + ['FUNCTION f POINTS 0 0 1 1', 'IMPOSE a UX FUNCTION f'], None, [], 16, 'IMPOSE a',
     'UX'),
    ('IMPOSE on a DOF the node lacks', BASE + ['FUNCTION f POINTS 0 0 1 1', 'IMPOSE b RZ FUNCTION f'], None, [], 16,
     'IMPOSE b', 'RZ'),
    ('IMPOSE without FUNCTION', BASE + ['IMPOSE b UX VALUE 2'], None, [], 15, 'IMPOSE b', 'b'),
    ('IMPOSE twice on one DOF', edit(BASE, 12, None) + ['FUNCTION f POINTS 0 0 1 1', 'IMPOSE b UX FUNCTION f',
                                                        'IMPOSE b UX VALUE 2 FUNCTION f'], None, [], 16, 'IMPOSE b', 'b'),
    ('DAMPING ALPHA twice', edit(BASE, 8, 'MODEL s MATERIAL k DAMPING ALPHA 1 ALPHA 2'), None, [], 8, 'MODEL s',
     'ALPHA'),
    ('DAMPING beyond 1e100', edit(BASE, 8, 'MODEL s MATERIAL k DAMPING BETA 1e200'), None, [], 8, 'MODEL s', '1e200'),
    ('IMPOSE with two DOFs', BASE + ['FUNCTION f POINTS 0 0 1 1', 'IMPOSE b UX UY FUNCTION f'], None, [], 16,
     'IMPOSE b', 'b'),
    ('bad --set value', BASE, None, ['TIME.STEP=abc'], 13, 'TIME', 'abc'),
    ('non-positive --set TIME.STEP', BASE, None, ['TIME.STEP=-1'], 13, 'TIME', '-1'),
    ('--set unknown keyword', BASE, None, ['TIMES.STEP=1'], None, '--set', 'TIMES'),
    ('--set unknown parameter', BASE, None, ['TIME.STOP=1'], None, '--set', 'STOP'),
    # Issue 33: FRICTION mu >= 0 and finite, on OBSTACLE and GAP only, where its tangent is fixed
    # (no curved obstacle), never with MASSLESS's inertia-free contact nodes.
    ('negative FRICTION', BASE + ['OBSTACLE wall NODES b POINT 2 0 NORMAL -1 0 FRICTION -0.1'], None, [], 15,
     'OBSTACLE wall', '-0.1'),
    ('FRICTION not finite', BASE + ['GAP g PAIRS a b FRICTION inf'], None, [], 15, 'GAP g', 'inf'),
    ('FRICTION on a FIX', edit(BASE, 11, 'FIX b UY FRICTION 0.3'), None, [], 11, 'FIX', 'FRICTION'),
    ('FRICTION on an IMPOSE', BASE + ['FUNCTION f POINTS 0 0 1 1', 'IMPOSE b UY FUNCTION f FRICTION 0.3'], None, [], 16,
     'IMPOSE', 'FRICTION'),
    ('FRICTION with IMPACT MASSLESS', BASE + ['OBSTACLE wall NODES b POINT 2 0 NORMAL -1 0 FRICTION 0.3',
                                              'SCHEME IMPACT MASSLESS'], None, [], 15, 'OBSTACLE wall', 'FRICTION'),
    ('FRICTION on a curved obstacle', BASE + ['OBSTACLE wall NODES b CYLINDER 3 0 RADIUS 1 OUTSIDE FRICTION 0.3'], None,
     [], 15, 'OBSTACLE wall', 'FRICTION'),
    ('--set ambiguous statement', edit(BASE, 6, 'MATERIAL k ELASTIC YOUNG 8\nMATERIAL k2 ELASTIC YOUNG 9'), None,
     ['MATERIAL.YOUNG=3'], None, '--set', 'MATERIAL occurs 2 times'),
]


def run_case(name, lines, extra, sets):
    path = write(name.replace(' ', '_').replace('.', '').replace('-', ''), lines, extra)
    outdir = sc.new_dir('out')
    rc, err, _ = sc.run(path, sets, outdir=outdir)
    return path, outdir, rc, err


for name, lines, extra, sets, line, keyword, word in CASES:
    path, outdir, rc, err = run_case(name, lines, extra, sets)
    msg = (err.strip().splitlines() or [''])[0]
    sc.report(name + ': exit 2', rc == 2, 'exit %d vs 2; stderr: %s' % (rc, msg[:300]))
    if line is not None:
        where = '%s:%d:' % (path, line)
        sc.report(name + ': names file and line', where in err, 'no "%s" in: %s' % (where, msg[:300]))
    sc.report(name + ': names the statement ' + keyword, keyword in err, 'no "%s" in: %s' % (keyword, msg[:300]))
    shown = word if ' ' in word or word.startswith('"') else "'%s'" % word
    sc.report(name + ': names the word at fault', shown in err, 'no %s in: %s' % (shown, msg[:300]))
    sc.report(name + ': no output directory created', not os.path.exists(outdir), outdir + ' exists')

# A DOF with neither mass nor stiffness: remove the point mass and the UY support of b, whose
# only element is a spring along x. The message must name the node and the DOF; a line number,
# if any, must be that of the node's statement (NODE b, line 3), not an unrelated one.
name = 'DOF with neither mass nor stiffness'
path, outdir, rc, err = run_case(name, edit(edit(BASE, 11, None), 9, None), None, [])
msg = (err.strip().splitlines() or [''])[0]
sc.report(name + ': exit 2', rc == 2, 'exit %d vs 2; stderr: %s' % (rc, msg[:300]))
sc.report(name + ': names the file', path in err, msg[:300])
node_named = "'b'" in err or 'node b' in err or ('node 2' in err and 'x = 1' in err)
sc.report(name + ': names the node (b, node 2 at x = 1, y = 0) and DOF UY', node_named and 'UY' in err, msg[:300])
bad_line = any('%s:%d:' % (path, k) in err for k in range(1, 20) if k != 3)
sc.report(name + ': no misleading line number (only NODE b, line 3, would be right)', not bad_line, msg[:300])
sc.report(name + ': no output directory created', not os.path.exists(outdir), outdir + ' exists')

# Zero density is legitimate: a massless BAR2 (EA/L = 8e4 * 1e-4 / 1 = 8 N/m) carrying a 2 kg
# point mass runs, and oscillates at omega = 2 rad/s with the scheme's period
# 2 pi h / (2 atan(omega h / 2)) (recurrence cos(Omega h) = (u[n-1] + u[n+1]) / (2 u[n])).
name = 'zero density'
lines = edit(edit(edit(BASE, 4, 'ELEMENT s TYPE BAR2 NODES a b'), 6, 'MATERIAL k ELASTIC YOUNG 8e4 DENSITY 0'),
             8, 'SECTION tube AREA 1e-4\nMODEL s MATERIAL k SECTION tube')
lines = edit(lines, 14, 'TIME STEP 0.1 END 10')
path, outdir, rc, err = run_case(name, lines, None, [])
sc.report(name + ': massless bar with a point mass runs (exit 0)', rc == 0, 'exit %d; stderr: %s' % (rc, err.strip()))
if rc == 0:
    u = sc.probes(outdir)['b.UX']
    k = 1 + int(np.argmax(np.abs(u[1:-1])))
    h, omega = 0.1, 2.0
    period = 2 * math.pi * h / math.acos((u[k - 1] + u[k + 1]) / (2 * u[k]))
    sc.close(name + ': period of the mass on the massless bar', period,
             2 * math.pi * h / (2 * math.atan(omega * h / 2)), 1e-10)
