"""A full disk is an error, never a success (issue 12, item 1).

Two ways to run out of room, so that the check works on any machine:
- a file size limit (RLIMIT_FSIZE, `ulimit -f`): every write past it fails with EFBIG;
- a small tmpfs (only as root where mount works; otherwise its lines are skipped).
Asserted: exit 1 with one message naming the file and the cause, never "results in"; every CSV
ends with a complete line; a checkpoint is never left half-written (no checkpoint.h5.tmp) and a
restart from whatever checkpoint.h5 survived continues bit for bit; a restart that cannot
rewrite history.csv leaves it as it was; fields.xmf lists only steps that fields.h5 holds.
"""
import os
import re
import resource
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

CPU_LIMIT = 120   # CPU seconds per run: a wide margin, never the wall clock


def limited(fsize):
    def pre():
        resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
        resource.setrlimit(resource.RLIMIT_CPU, (CPU_LIMIT, CPU_LIMIT))
    return pre


def rebond(scene, outdir, sets=(), fsize=None, restart=None):
    cmd = [sc.REBOND, scene, '-o', outdir, '--quiet']
    for s in sets:
        cmd += ['--set', s]
    if restart:
        cmd += ['--restart', restart]
    p = subprocess.run(cmd, cwd=sc.ROOT, capture_output=True, text=True,
                       preexec_fn=limited(fsize if fsize else resource.RLIM_INFINITY))
    return p.returncode, p.stderr


def read(path):
    with open(path, 'rb') as f:
        return f.read()


def complete_lines(outdir):
    """Every CSV of outdir ends with a newline and has as many fields on each line as its header."""
    bad = []
    for name in sorted(os.listdir(outdir)):
        if not name.endswith('.csv'):
            continue
        rows = read(os.path.join(outdir, name)).decode().split('\n')
        ncol = rows[0].count(',') + 1
        if rows[-1] != '' or any(r.count(',') + 1 != ncol for r in rows[:-1]):
            bad.append(name)
    return bad


def one_message(err, path_part, cause):
    lines = sc.message_lines(err)
    return len(lines) == 1 and lines[0].startswith('rebond: error: ') and path_part in lines[0] and \
        cause in lines[0] and 'results in' not in err


def csv_limits():
    # mass_bounce: history.csv ~ 35k lines; the limit cuts it at several places.
    full = sc.run_ok('inputs/mass_bounce.dat')
    nfull = read(os.path.join(full, 'history.csv')).count(b'\n')
    for kib in (16, 64, 333):
        out = sc.new_dir('fsize')
        rc, err = rebond('inputs/mass_bounce.dat', out, fsize=kib * 1024)
        n = read(os.path.join(out, 'history.csv')).count(b'\n')
        tag = 'file size limit %d KiB: ' % kib
        sc.report(tag + 'exit 1 with one message naming the file and the cause',
                  rc == 1 and one_message(err, '.csv', 'File too large'), 'exit %d, %r' % (rc, err[-300:]))
        sc.report(tag + 'complete lines only', not complete_lines(out), complete_lines(out))
        sc.report(tag + 'history.csv stopped short', 1 < n < nfull, '%d of %d lines' % (n, nfull))
        # What was written is what a full run wrote (a prefix).
        sc.report(tag + 'the lines written are those of the full run',
                  read(os.path.join(full, 'history.csv')).startswith(read(os.path.join(out, 'history.csv'))), out)


def restart_keeps_history():
    # A restart that cannot rewrite history.csv (limit below its size) leaves it as it was.
    sets = ['OUTPUT.CHECKPOINT=100', 'OUTPUT.FIELDS=0']
    out = sc.new_dir('resume')
    rc, err = rebond('inputs/spring_plastic.dat', out, sets)
    before = read(os.path.join(out, 'history.csv'))
    rc, err = rebond('inputs/spring_plastic.dat', out, sets, fsize=len(before) // 2,
                     restart=os.path.join(out, 'checkpoint.h5'))
    sc.report('restart under a limit: exit 1 naming history.csv.tmp',
              rc == 1 and one_message(err, 'history.csv.tmp', 'File too large'), 'exit %d, %r' % (rc, err[-300:]))
    sc.report('restart under a limit: history.csv untouched', read(os.path.join(out, 'history.csv')) == before,
              'history.csv changed')
    sc.report('restart under a limit: no .tmp left', not [f for f in os.listdir(out) if f.endswith('.tmp')],
              os.listdir(out))


def checkpoint_limit():
    # The checkpoint (~7 KiB) does not fit under a 4 KiB limit; HISTORY 0 keeps the CSVs small.
    sets = ['OUTPUT.CHECKPOINT=50', 'OUTPUT.FIELDS=0', 'OUTPUT.HISTORY=0']
    out = sc.new_dir('ckpt')
    rc, err = rebond('inputs/spring_plastic.dat', out, sets, fsize=4096)
    sc.report('checkpoint under a limit: exit 1 naming checkpoint.h5.tmp',
              rc == 1 and one_message(err, 'checkpoint.h5.tmp', 'File too large'), 'exit %d, %r' % (rc, err[-300:]))
    sc.report('checkpoint under a limit: nothing half-written left',
              sorted(os.listdir(out)) == ['history.csv', 'probes.csv'], os.listdir(out))


def fields_check(outdir):
    """(steps listed by fields.xmf, all of them readable in fields.h5)."""
    import h5py
    xml = read(os.path.join(outdir, 'fields.xmf')).decode()
    ET.fromstring(xml)
    steps = re.findall(r'fields\.h5:/(step_\d+)/displacement', xml)
    with h5py.File(os.path.join(outdir, 'fields.h5'), 'r') as f:
        ok = all(s in f and f[s]['displacement'][()].shape[0] > 0 for s in steps)
    return steps, ok


def fields_limits():
    sets = ['TIME.END=0.05', 'OUTPUT.FIELDS=5']
    for kib in (110, 160, 240):   # (a step of the cantilever takes about 25 KiB with its XDMF grid)
        out = sc.new_dir('fields')
        rc, err = rebond('inputs/cantilever_release.dat', out, sets, fsize=kib * 1024)
        tag = 'fields under a %d KiB limit: ' % kib
        sc.report(tag + 'exit 1 with one message (no HDF5 dump, no crash)',
                  rc == 1 and one_message(err, 'fields.h5', 'no room left'), 'exit %d, %r' % (rc, err[-300:]))
        steps, ok = fields_check(out)
        sc.report(tag + 'fields.xmf lists only steps fields.h5 holds', ok and len(steps) >= 1, '%d steps' % len(steps))


def tmpfs_sweep():
    """As root: the full-disk cases on a real small file system."""
    mnt = sc.new_dir('tmpfs')
    os.makedirs(mnt)
    if os.geteuid() != 0 or subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=200k', 'tmpfs', mnt],
                                           capture_output=True).returncode != 0:
        print('SKIP tmpfs cases: mount needs root')
        return
    try:
        out = os.path.join(mnt, 'out')
        rc, err = rebond('inputs/mass_bounce.dat', out)
        sc.report('200 KiB tmpfs: exit 1, "No space left on device"',
                  rc == 1 and one_message(err, '.csv', 'No space left on device'), 'exit %d, %r' % (rc, err[-300:]))
        sc.report('200 KiB tmpfs: complete lines only', not complete_lines(out), complete_lines(out))
        # A checkpoint every 50 steps of the plastic spring, on disks of 20..76 KiB: whatever
        # checkpoint.h5 is left restarts to the full run's history, bit for bit.
        sets = ['OUTPUT.CHECKPOINT=50', 'OUTPUT.FIELDS=0']
        full = sc.run_ok('inputs/spring_plastic.dat', sets)
        restarts, good, clean = 0, 0, True
        for kib in range(20, 80, 4):
            subprocess.run(['umount', mnt], check=True)
            subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=%dk' % kib, 'tmpfs', mnt], check=True)
            rc, err = rebond('inputs/spring_plastic.dat', out, sets)
            clean = clean and rc == 1 and not [f for f in os.listdir(out) if f.endswith('.tmp')]
            if os.path.exists(os.path.join(out, 'checkpoint.h5')):
                copy = sc.new_dir('copy')
                shutil.copytree(out, copy)
                restarts += 1
                rc2, _ = rebond('inputs/spring_plastic.dat', copy, sets, restart=os.path.join(copy, 'checkpoint.h5'))
                good += rc2 == 0 and read(os.path.join(copy, 'history.csv')) == read(os.path.join(full, 'history.csv'))
        sc.report('tmpfs 20..76 KiB: every run exit 1, no .tmp left', clean, 'a run passed or left a .tmp')
        sc.report('tmpfs: every surviving checkpoint restarts bit for bit', restarts > 5 and good == restarts,
                  '%d of %d' % (good, restarts))
    finally:
        subprocess.run(['umount', mnt], capture_output=True)


def stdout_full():
    """Standard output on /dev/full (issue 37): the report cannot be written, so exit 1 with a
    message on stderr, and the results are complete (history.csv as a run to a good stdout)."""
    if not os.path.exists('/dev/full'):
        print('# /dev/full missing: skipped')
        return
    ref = sc.run_ok('inputs/spring_plastic.dat')
    out = sc.new_dir('devfull')
    with open('/dev/full', 'w') as full:
        p = subprocess.run([sc.REBOND, 'inputs/spring_plastic.dat', '-o', out], stdout=full, stderr=subprocess.PIPE,
                           text=True, cwd=sc.ROOT, preexec_fn=limited(1 << 40))
    sc.report('stdout on /dev/full: exit 1 with a message', p.returncode == 1 and 'standard output' in p.stderr,
              'exit %d: %s' % (p.returncode, p.stderr.strip()[-200:]))
    sc.report('stdout on /dev/full: the results complete', read(os.path.join(out, 'history.csv')) ==
              read(os.path.join(ref, 'history.csv')))


csv_limits()
stdout_full()
restart_keeps_history()
checkpoint_limit()
fields_limits()
tmpfs_sweep()
