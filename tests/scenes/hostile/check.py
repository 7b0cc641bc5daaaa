"""Hostile input: what the user typed is what runs, and every refusal is one clear message
(issue 12, items 3-5). `make check-debug` runs this check again on bin/rebond-debug (bounds
checks and FPE traps), where an overflow in the input handling would trap.

- --set values of any length (a 516-character YOUNG, 100 probes in one --set) are used whole;
- TIME STEP 4.9e-324 / 1e300, END 1e308, START -1e308: exit 2 naming TIME, no FPE;
- a free DOF without mass, a PROBE of a DOF its node does not carry: exit 2, named;
- a directory given as a mesh, a mesh of raw bytes: exit 2, said so, no byte echoed;
- a UTF-8 byte order mark and CR-only line ends (scene and Gmsh file): read, same results;
- symbolic links planted at the result paths: replaced, their targets untouched;
- out of memory on an allowed size (10 000 000 elements under a 3 GB address-space limit):
  exit 1 with one message, no runtime backtrace.
"""
import os
import resource
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

TMP = sc.new_dir('hostile')
os.makedirs(TMP)


def refused(tag, scene, sets=(), code=2, words=(), line=None):
    out = sc.new_dir('never')
    rc, err, _ = sc.run(scene, sets, outdir=out)
    lines = sc.message_lines(err)
    msg = '\n'.join(lines)
    ok = rc == code and msg.startswith('rebond: error: ') and len(lines) == 1 and \
        all(w in msg for w in words) and not os.path.exists(out) and msg.isprintable()
    if line is not None:
        ok = ok and ('%s:%d:' % (scene, line)) in msg
    sc.report(tag, ok, 'exit %d: %r' % (rc, msg[:400]))


def same_run(tag, scene_a, scene_b, sets=()):
    a = sc.run_ok(scene_a, sets)
    b = sc.run_ok(scene_b, sets)
    same = open(os.path.join(a, 'history.csv'), 'rb').read() == open(os.path.join(b, 'history.csv'), 'rb').read()
    sc.report(tag, same, '%s vs %s' % (a, b))
    return b


def long_set_values():
    young = '2.1' + '0' * 510 + 'e11'   # 516 characters, the value 2.1e11
    sets = ['TIME.END=1e-4']
    a = sc.run_ok('inputs/bar_impact.dat', sets)
    b = sc.run_ok('inputs/bar_impact.dat', sets + ['MATERIAL.steel.YOUNG=' + young])
    same = open(os.path.join(a, 'history.csv'), 'rb').read() == open(os.path.join(b, 'history.csv'), 'rb').read()
    sc.report('a 516-character --set YOUNG is the value typed', same, 'histories differ')
    probes = ' '.join(['ball UY'] * 100)
    out = sc.run_ok('inputs/mass_bounce.dat', ['TIME.END=0.1', 'OUTPUT.PROBE=' + probes])
    with open(os.path.join(out, 'probes.csv')) as f:
        ncol = f.readline().count(',') + 1
    sc.report('100 probes in one --set give 100 columns', ncol == 102, '%d columns' % ncol)


def time_extremes():
    for s in ('TIME.STEP=4.9e-324', 'TIME.STEP=1e-320', 'TIME.END=1e308', 'TIME.START=-1e308', 'TIME.STEP=1e300'):
        refused('%s refused, named' % s, 'inputs/mass_bounce.dat', [s], words=('TIME',))


def model_defects():
    base = ['NODE a AT 0 0', 'NODE b AT 1 0', 'ELEMENT s TYPE SPRING NODES a b',
            'MATERIAL k ELASTIC YOUNG 1 DENSITY 0', 'SECTION sc AREA 1', 'MODEL s MATERIAL k SECTION sc',
            'FIX a UX UY', 'FIX b UY', 'INITIAL b DISPLACEMENT 0.1 0', 'TIME STEP 0.1 END 1']
    refused('a free DOF without mass refused, node and DOF named', sc.write_scene('massless.dat', '\n'.join(base) + '\n'),
            words=('node 2', 'UX', 'no mass'), line=2)
    pm = ['NODE ball AT 0 1', 'ELEMENT pm TYPE MASS NODES ball', 'SECTION m1 MASS 1', 'MODEL pm SECTION m1',
          'TIME STEP 0.1 END 1', 'OUTPUT PROBE ball RZ']
    refused('PROBE RZ of a point mass refused', sc.write_scene('probe_rz.dat', '\n'.join(pm) + '\n'),
            words=('PROBE', 'RZ'), line=6)


GMSH_SCENE = """GMSH      sq FILE {mesh}
MATERIAL  rubber ELASTIC YOUNG 1e6 POISSON 0.45 DENSITY 1100
SECTION   sheet THICKNESS 0.01
MODEL     sq.body MATERIAL rubber SECTION sheet PLANE STRESS
FIX       sq.left ALL
INITIAL   sq.right VELOCITY 0.2 1
TIME      STEP 1e-3 END 0.05
"""


def files_that_are_not_meshes():
    d = os.path.join(TMP, 'a_directory.msh')
    os.makedirs(d)
    refused('a directory given as a mesh: said so', sc.write_scene('dir.dat', GMSH_SCENE.format(mesh=d)),
            words=('is a directory',), line=1)
    raw = sc.write_scene('raw.msh', bytes(range(256)) * 12)
    refused('a mesh of raw bytes: refused, no byte echoed', sc.write_scene('raw.dat', GMSH_SCENE.format(mesh=raw)),
            words=('binary data',), line=1)


def line_ends():
    text = open(os.path.join(sc.ROOT, 'inputs/mass_bounce.dat'), 'rb').read()
    bom = sc.write_scene('bom.dat', b'\xef\xbb\xbf' + text)
    cr = sc.write_scene('cr.dat', text.replace(b'\n', b'\r'))
    crlf = sc.write_scene('crlf.dat', text.replace(b'\n', b'\r\n'))
    sets = ['TIME.END=0.5']
    same_run('a scene with a UTF-8 BOM runs as the plain one', 'inputs/mass_bounce.dat', bom, sets)
    same_run('a scene with CR-only line ends runs as the plain one', 'inputs/mass_bounce.dat', cr, sets)
    same_run('a scene with CR LF line ends runs as the plain one', 'inputs/mass_bounce.dat', crlf, sets)
    mesh = open(os.path.join(sc.ROOT, 'tests/data/square_quad4.msh'), 'rb').read()
    plain = sc.write_scene('m_plain.dat', GMSH_SCENE.format(mesh=os.path.join(sc.ROOT, 'tests/data/square_quad4.msh')))
    for tag, data in (('a UTF-8 BOM', b'\xef\xbb\xbf' + mesh), ('CR-only line ends', mesh.replace(b'\n', b'\r'))):
        m = sc.write_scene('m_%d.msh' % len(tag), data)
        same_run('a Gmsh file with %s reads as the plain one' % tag, plain, sc.write_scene('m_%d.dat' % len(tag),
                 GMSH_SCENE.format(mesh=m)))


def symlinks():
    out = os.path.join(TMP, 'links')
    os.makedirs(out)
    target = sc.write_scene('precious.txt', 'precious\n')
    names = ['history.csv', 'probes.csv', 'fields.h5', 'fields.xmf', 'checkpoint.h5']
    for n in names:
        os.symlink(target, os.path.join(out, n))
    rc, err, _ = sc.run('inputs/cantilever_release.dat', ['TIME.END=1e-3', 'OUTPUT.CHECKPOINT=5'], outdir=out)
    kept = open(target).read() == 'precious\n'
    replaced = all(os.path.isfile(os.path.join(out, n)) and not os.path.islink(os.path.join(out, n)) for n in names)
    sc.report('symbolic links at the result paths replaced, their target untouched', rc == 0 and kept and replaced,
              'exit %d, target kept %s, replaced %s' % (rc, kept, replaced))


def out_of_memory():
    scene = sc.write_scene('big.dat', '\n'.join([
        'MATERIAL st ELASTIC YOUNG 2e11 DENSITY 7800', 'SECTION sc AREA 1e-4 INERTIA 1e-9 HEIGHT 0.01',
        'LINE b FROM 0 0 TO 1 0 ELEMENTS 10000000 TYPE BEAM2', 'MODEL b MATERIAL st SECTION sc',
        'FIX b.start UX UY RZ', 'TIME STEP 1e-5 END 3e-5']) + '\n')
    limit = 3 * 1024 ** 3

    def pre():
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    out = sc.new_dir('oom')
    p = subprocess.run([sc.REBOND, scene, '-o', out, '--quiet'], capture_output=True, text=True, preexec_fn=pre,
                       timeout=600)
    lines = sc.message_lines(p.stderr)
    msg = '\n'.join(lines)
    sc.report('out of memory on an allowed size: exit 1, one message, no backtrace',
              p.returncode == 1 and msg.startswith('rebond: error: out of memory') and len(lines) == 1,
              'exit %d: %r' % (p.returncode, msg[:400]))


long_set_values()
time_extremes()
model_defects()
files_that_are_not_meshes()
line_ends()
symlinks()
# Under valgrind or a sanitizer the address-space limit is meaningless.
if 'valgrind' not in sc.REBOND:
    out_of_memory()
shutil.rmtree(TMP, ignore_errors=True)
