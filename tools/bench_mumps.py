#!/usr/bin/python3
"""SCHEME SOLVER (issue 34): CHOLMOD, MUMPS in one process and MUMPS on two MPI ranks on 3D HEX8
blocks, run by `make bench`; writes docs/performance-mumps.md.

    tools/bench_mumps.py [REBOND] [OUT.md] [--sizes 1e4,1e5]

Also the communication between the 2 ranks per step (Open MPI's pml/coll monitoring components).
The block: a cube of n x n x n HEX8, ELASTIC steel, fixed at its base, a pulse of pressure-like
nodal forces on its top, STEPS steps of TIME STEP 1e-6 (linear: one solve a step with K0 u).
For each size and solver: the analysis CPU (rank 0, from the run's summary), the factorization
and the solves (count, CPU and wall seconds of rank 0, from the summary's `linear solves` line),
the time loop's wall per step over the solve's wall per step (the step/solve ratio), the CPU of
every process of the run (getrusage of the children: mpirun's ranks included) and the peak
resident set of each rebond process (GNU time around each rank). OpenBLAS on one thread.
"""
import math
import os
import re
import resource
import shutil
import subprocess
import sys
import tempfile

SCENE = """DIMENSION 3
TITLE     "HEX8 block for the solver bench"
BOX       blk ORIGIN 0 0 0 SIZE 1 1 1 ELEMENTS {n} {n} {n} TYPE HEX8
MATERIAL  el ELASTIC YOUNG 2.1e11 POISSON 0.3 DENSITY 7800
MODEL     blk MATERIAL el
FIX       blk.zmin UX UY UZ
FUNCTION  pulse POINTS 0 0 5e-6 1 1 1
LOAD      push NODES blk.zmax FORCE 0 0 -1e3 FUNCTION pulse
TIME      STEP 1e-6 END {end}
OUTPUT    HISTORY EVERY 0 FIELDS EVERY 0
"""
STEPS = 50
ENV = dict(os.environ, OPENBLAS_NUM_THREADS='1', OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
           OMPI_MCA_rmaps_base_oversubscribe='1')


def run(cmd):
    """stdout, the CPU of every process, the peak RSS of each rebond process (MB; GNU time on each)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise RuntimeError('%s: exit %d\n%s' % (' '.join(cmd), p.returncode, p.stderr[-800:]))
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    rss = [int(x) / 1024.0 for x in re.findall(r'^peak_rss_kb (\d+)$', p.stderr, re.M)]
    return p.stdout, cpu, rss


def parse(out):
    r = {}
    m = re.search(r'(\d+) equations', out)
    r['neq'] = int(m.group(1))
    m = re.search(r'(\d+) steps in ([\d.]+) s', out)
    r['steps'], r['loop_wall'] = int(m.group(1)), float(m.group(2))
    m = re.search(r'nnz\(L\) = (\d+), (.*) ordering \(analysis ([\d.]+) s CPU\)', out)
    r['nnz'], r['ordering'], r['analysis'] = int(m.group(1)), m.group(2), float(m.group(3))
    m = re.search(r'linear solves \((\w+)\): (\d+) factorizations in ([\d.]+) s CPU \(([\d.]+) s wall\), (\d+) solves in '
                  r'([\d.]+) s CPU \(([\d.]+) s wall\)', out)
    e = re.search(r"MUMPS's estimates: +([\d.E+-]+) flops, +([\d.E+-]+) factor entries; in core (\d+) MB on the busiest "
                  r"rank \((\d+) MB in all\), out of core (\d+) MB \((\d+) MB\)", out)
    if e:
        r.update(est_flops=float(e.group(1)), est_entries=float(e.group(2)), mem_rank=int(e.group(3)),
                 mem_all=int(e.group(4)), ooc_rank=int(e.group(5)), ooc_all=int(e.group(6)))
    if m:
        r.update(lib=m.group(1), nfac=int(m.group(2)), fac_cpu=float(m.group(3)), fac_wall=float(m.group(4)),
                 nsol=int(m.group(5)), sol_cpu=float(m.group(6)), sol_wall=float(m.group(7)))
    return r


def reading(rows):
    """The table of the largest size in words (computed from it)."""
    big = [r for r in rows if r['size'] == rows[-1]['size'] and 'lib' in r]
    if len(big) < 3:
        return ['']
    c, m1, m2 = big
    def per(r, k, n):
        return r[k] / r[n]
    return ['', 'At %d equations: a factorization takes %.2f s wall with CHOLMOD, %.2f s with MUMPS in one process and %.2f s'
            % (c['neq'], per(c, 'fac_wall', 'nfac'), per(m1, 'fac_wall', 'nfac'), per(m2, 'fac_wall', 'nfac')),
            'on 2 ranks; a solve %.0f, %.0f and %.0f ms. MUMPS\'s factor has %.0f %% more entries than CHOLMOD\'s (its'
            % (1e3 * per(c, 'sol_wall', 'nsol'), 1e3 * per(m1, 'sol_wall', 'nsol'), 1e3 * per(m2, 'sol_wall', 'nsol'),
               100.0 * (m2['nnz'] / c['nnz'] - 1.0)),
            'SCOTCH ordering against CHOLMOD\'s nested dissection of supervariables), so on one process CHOLMOD is the',
            'faster and stays the default; the second rank brings MUMPS\'s solve to %.2f and its factorization to %.2f'
            % (per(m2, 'sol_wall', 'nsol') / per(c, 'sol_wall', 'nsol'), per(m2, 'fac_wall', 'nfac') / per(c, 'fac_wall', 'nfac')),
            'of CHOLMOD\'s, and splits the factors\' memory (peak RSS per process above). The step costs %.2f solves on'
            % ((m2['loop_wall'] / m2['steps']) / per(m2, 'sol_wall', 'nsol')),
            '2 ranks (issue 34 asks at most 1.3): the time loop on rank 0 adds little to the distributed solve on a',
            'linear scene. The run\'s CPU counts both ranks, the waiting one polling in MPI_Bcast.', '']


def projection(rows):
    """A projection (labelled so) to more ranks and larger blocks from MUMPS's own estimates at the
    measured sizes (a power law in the equations through the two largest) and the rate measured on
    two ranks (flops of the factorization over its wall, per rank)."""
    m2 = [r for r in rows if r['case'].startswith('MUMPS, mpirun') and 'est_flops' in r]
    if len(m2) < 2:
        return ['']
    a, b = m2[-2], m2[-1]
    lg = math.log(b['neq'] / a['neq'])
    pf = math.log(b['est_flops'] / a['est_flops']) / lg
    pm = math.log(b['mem_all'] / a['mem_all']) / lg
    po = math.log(b['ooc_all'] / a['ooc_all']) / lg
    rate = b['est_flops'] / (b['fac_wall'] / b['nfac']) / 2.0
    out = ['', '## Projection (not a measurement)', '',
           'From MUMPS\'s estimates after its analysis at %d and %d equations (flops ∝ n^%.2f, working memory in'
           % (a['neq'], b['neq'], pf),
           'core ∝ n^%.2f, out of core ∝ n^%.2f) and the factorization rate measured here on 2 ranks, %.1f Gflop/s per'
           % (pm, po, rate / 1e9),
           'rank, assumed to hold on every rank (ideal scaling: a lower bound on the time). Memory per rank: the',
           'in-core total over the ranks (MUMPS\'s busiest rank carried %.2f of the 2 ranks\' total here).'
           % (b['mem_rank'] / b['mem_all']), '',
           '| equations | factorization flops | in core, all ranks | out of core, all ranks | '
           'factorization on 8 / 64 / 512 ranks | in core per rank on 8 / 64 / 512 |',
           '|---:|---:|---:|---:|---:|---:|']
    for n in (1e6, 1e7, 1e8):
        fl = b['est_flops'] * (n / b['neq']) ** pf
        mem = b['mem_all'] * (n / b['neq']) ** pm / 1024.0
        ooc = b['ooc_all'] * (n / b['neq']) ** po / 1024.0
        t = ' / '.join(fmt_time(fl / (p * rate)) for p in (8, 64, 512))
        mr = ' / '.join('%.1f GB' % (mem / p) for p in (8, 64, 512))
        out.append('| %.0e | %.1e | %.0f GB | %.0f GB | %s | %s |' % (n, fl, mem, ooc, t, mr))
    out += ['', 'Ranks needed so that each holds at most 20 GB in core (a 24 GiB node with room for the rest):', '']
    for p in (1, 8, 64, 512):
        nmax = b['neq'] * (20.0 * 1024 * p / b['mem_all']) ** (1.0 / pm)
        out.append('- %d rank(s): up to about %.1e equations' % (p, nmax))
    n24 = b['neq'] * (24.0 * 1024 / b['mem_all']) ** (1.0 / pm)
    ooc24 = b['ooc_all'] * (n24 / b['neq']) ** po / 1024.0
    fl24 = b['est_flops'] * (n24 / b['neq']) ** pf
    out += ['', 'OUT_OF_CORE on this machine: the in-core working memory passes 24 GiB at about %.1e equations, where'
            % n24, 'out of core needs about %.0f GB; its factorization, %.1e flops, would take about %s at the rate'
            % (ooc24, fl24, fmt_time(fl24 / (2 * rate))),
            'measured on 2 ranks. Run once by hand at 971 244 equations (docs/parallel.md): MUMPS\'s own estimates',
            'there were 2.05e13 flops and 32.6 GB in core (the power law above from the two smaller sizes',
            'underestimates both), out of core it ran in 15.9 GB, its factorization in 442 s.',
            '']
    return out


def fmt_time(sec):
    if sec < 120:
        return '%.0f s' % sec
    if sec < 7200:
        return '%.0f min' % (sec / 60)
    return '%.1f h' % (sec / 3600)


def comm_volume(mpirun, rebond, scene_text, work, steps):
    """Bytes and messages the ranks send each other in a run of `steps` steps (Open MPI's monitoring
    components: point to point, MUMPS's own and inside collectives, summed over both ranks)."""
    scene = os.path.join(work, 'mon_%d.dat' % steps)
    with open(scene, 'w') as f:
        f.write(scene_text.replace('END {end}', 'END %r' % (steps * 1e-6)))
    prefix = os.path.join(work, 'mon_%d' % steps)
    cmd = [mpirun, '--oversubscribe', '--mca', 'pml_monitoring_enable', '2', '--mca', 'pml_monitoring_enable_output',
           '3', '--mca', 'pml_monitoring_filename', prefix, '-np', '2', rebond, scene, '-o', work + '/mon', '-q']
    p = subprocess.run(cmd, capture_output=True, text=True, env=ENV)
    if p.returncode != 0:
        raise RuntimeError('%s: exit %d\n%s' % (' '.join(cmd), p.returncode, p.stderr[-800:]))
    nbytes = nmsg = 0
    for rank in (0, 1):
        with open('%s.%d.prof' % (prefix, rank)) as f:
            for line in f:
                m = re.match(r'^[EI]\t\d+\t\d+\t(\d+) bytes\t(\d+) msgs sent', line)
                if m:
                    nbytes += int(m.group(1))
                    nmsg += int(m.group(2))
    return nbytes, nmsg


def main(argv):
    args = [a for a in argv[1:] if not a.startswith('--')]
    rebond = args[0] if args else 'bin/rebond'
    out_md = args[1] if len(args) > 1 else 'docs/performance-mumps.md'
    sizes = ['1e4', '1e5']
    for a in argv[1:]:
        if a.startswith('--sizes='):
            sizes = a.split('=', 1)[1].split(',')
    mpirun = shutil.which('mpirun')
    work = tempfile.mkdtemp(prefix='rebond-mumps.')
    rows = []
    for size in sizes:
        n = max(2, round((float(size) / 3.0) ** (1.0 / 3.0)) - 1)
        scene = os.path.join(work, 'block_%s.dat' % size)
        with open(scene, 'w') as f:
            f.write(SCENE.format(n=n, end=repr(STEPS * 1e-6)))
        gtime = ['/usr/bin/time', '-f', 'peak_rss_kb %M']
        cases = [('CHOLMOD', gtime + [rebond, scene, '-o', work + '/c', '--set', 'SCHEME.SOLVER=CHOLMOD']),
                 ('MUMPS, 1 process', gtime + [rebond, scene, '-o', work + '/m1', '--set', 'SCHEME.SOLVER=MUMPS']),
                 ('MUMPS, mpirun -np 2', [mpirun, '--oversubscribe', '-np', '2'] + gtime + [rebond, scene, '-o',
                                                                                            work + '/m2'])]
        for name, cmd in cases:
            out, cpu, rss = run(cmd)
            r = parse(out)
            r.update(case=name, size=size, n=n, cpu=cpu, rss=rss)
            rows.append(r)
            print(name, size, r, flush=True)
        # Communication per step on 2 ranks: runs of 10 and 110 steps, the difference over 100 (the
        # set-up's own volume varies from run to run with MUMPS's dynamic mapping: a long difference).
        b10, m10 = comm_volume(mpirun, rebond, SCENE.format(n=n, end='{end}'), work, 10)
        b110, m110 = comm_volume(mpirun, rebond, SCENE.format(n=n, end='{end}'), work, 110)
        per, mper = (b110 - b10) / 100.0, (m110 - m10) / 100.0
        rows[-1].update(comm_step=per, msg_step=mper, comm_setup=b10 - 10 * per, msg_setup=m10 - 10 * mper)
        print('communication', size, rows[-1]['comm_step'], rows[-1]['comm_setup'], flush=True)
    write_report(rows, out_md)
    return 0


def write_report(rows, out_md):
    lines = ['# MUMPS against CHOLMOD on 3D blocks (generated by `tools/bench_mumps.py`, `make bench`)', '',
             'SCHEME SOLVER (docs/input.md; docs/parallel.md): a cube of n³ HEX8, ELASTIC, fixed at its base, a',
             'load pulse on its top, %d steps of 1 µs (linear: one solve a step). OpenBLAS on one thread; the' % STEPS,
             'machine has 2 cores, so `mpirun -np 2` uses both. Analysis: rank 0\'s CPU (MUMPS: JOB = 1);',
             'factorizations and solves: rank 0\'s CPU and the wall (the other rank works during the same calls);',
             'step/solve: the time loop\'s wall per step over the solves\' wall per step; CPU: every process of',
             'the run, set-up included; peak RSS: each process (rank 0 first under mpirun, as GNU time reports them).', '',
             '| equations | solver | ordering | nnz(L) | analysis (s CPU) | factorization (s CPU / wall) | '
             'solve (ms CPU / wall) | step/solve | run CPU (s) | peak RSS (MB) |',
             '|---:|---|---|---:|---:|---:|---:|---:|---:|---:|']
    for r in rows:
        if 'lib' in r:
            fac = '%.2f / %.2f' % (r['fac_cpu'] / r['nfac'], r['fac_wall'] / r['nfac'])
            sol = '%.2f / %.2f' % (1e3 * r['sol_cpu'] / r['nsol'], 1e3 * r['sol_wall'] / r['nsol'])
            ratio = '%.2f' % ((r['loop_wall'] / r['steps']) / (r['sol_wall'] / r['nsol']))   # one solve a step
        else:
            fac = sol = ratio = '—'
        lines.append('| %d | %s | %s | %d | %.2f | %s | %s | %s | %.1f | %s |'
                     % (r['neq'], r['case'], r['ordering'], r['nnz'], r['analysis'], fac, sol, ratio, r['cpu'],
                        ' + '.join('%.0f' % x for x in r['rss'])))
    lines += ['', 'Communication between the 2 ranks (Open MPI\'s monitoring components, point to point and inside',
              'collectives, both directions; per step: the difference of 10- and 110-step runs over 100 steps; set-up:',
              'the 10-step run less 10 steps, i.e. the analysis, the factorization and the report\'s solves):', '',
              '| equations | per step | messages per step | set-up |', '|---:|---:|---:|---:|']
    for r in rows:
        if 'comm_step' in r:
            lines.append('| %d | %.3g MB | %.0f | %.3g MB |' % (r['neq'], r['comm_step'] / 1e6, r['msg_step'],
                                                             r['comm_setup'] / 1e6))
    lines += ['', 'A solve moves the right-hand side to the ranks and the solution back, and the factors\' blocks',
              'between them: a few times the system\'s vector (%.1f MB at the largest size) a step.'
              % (8.0 * rows[-1]['neq'] / 1e6)]
    lines += reading(rows)
    lines += projection(rows)
    with open(out_md, 'w') as f:
        f.write('\n'.join(lines))
    print('\n'.join(lines))


if __name__ == '__main__':
    sys.exit(main(sys.argv))
