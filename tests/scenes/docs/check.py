"""Documentation that runs (issue 13, item 7): every scene fragment of README.md and
docs/input.md is a valid scene, and every `bin/rebond inputs/…` command of the README runs.

A fragment is a fenced (```) or indented block whose first statement starts with a keyword of
the scene grammar; grammar synopses (with `[`, `|` or `…`) are not scenes and are skipped. What a
fragment leaves out to be a whole scene is added around it (a point mass and its MODEL when it
has none, a TIME when it has none): the fragment's own statements must parse and build, exit 0.
"""
import os
import re
import shlex
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import scenecheck as sc  # noqa: E402

KEYWORDS = {'DIMENSION', 'ELEMENT', 'FIX', 'FUNCTION', 'GAP', 'GMSH', 'GRAVITY', 'GROUP', 'INITIAL', 'LINE', 'LOAD',
            'MATERIAL', 'MODEL', 'NODE', 'OBSTACLE', 'OUTPUT', 'RECTANGLE', 'SCHEME', 'SECTION', 'TIME', 'TITLE'}
FILES = ['README.md', 'docs/input.md']


def blocks(path):
    """[(first line number, lines)] of the fenced and indented blocks of a Markdown file."""
    lines = open(os.path.join(sc.ROOT, path), encoding='utf-8').read().split('\n')
    out, cur, fence, start = [], [], None, 0
    for i, ln in enumerate(lines, 1):
        s = ln.strip()
        if s.startswith('```'):
            if fence is not None:
                out.append((start, cur))
                cur, fence = [], None
            else:
                fence, start = len(ln) - len(ln.lstrip()), i + 1
            continue
        if fence is not None:
            cur.append(ln[fence:])
        elif ln.startswith('    ') and s:
            if not cur:
                start = i
            cur.append(ln[4:])
        elif cur:
            out.append((start, cur))
            cur = []
    if cur:
        out.append((start, cur))
    return out


def statements(block):
    return [ln for ln in block if ln.strip() and not ln.strip().startswith('#')]


def is_fragment(block):
    st = statements(block)
    if not st or st[0].split()[0].upper() not in KEYWORDS:
        return False
    return not any(c in ln for ln in st for c in '[|…')


def complete(block):
    text = '\n'.join(block)
    words = {ln.split()[0].upper() for ln in statements(block) if ln.split()}
    extra = []
    if 'MODEL' not in words:
        extra += ['NODE doc_node AT 5 5', 'ELEMENT doc_pm TYPE MASS NODES doc_node', 'SECTION doc_section MASS 1',
                  'MODEL doc_pm SECTION doc_section']
    if 'TIME' not in words:
        extra.append('TIME STEP 1e-4 END 3e-4')
    return text + '\n' + '\n'.join(extra) + '\n'


def fragments():
    n = 0
    os.makedirs(sc.TMP, exist_ok=True)
    for path in FILES:
        for line, block in blocks(path):
            if not is_fragment(block):
                continue
            n += 1
            scene = os.path.join(sc.TMP, 'fragment_%d.dat' % n)
            with open(scene, 'w', encoding='utf-8') as f:
                f.write(complete(block))
            rc, err, _ = sc.run(scene, ['TIME.END=3e-4'])
            sc.report('%s:%d: the scene fragment runs' % (path, line), rc == 0, 'exit %d: %s' % (rc, err.strip()[-300:]))
    sc.report('fragments found in %s (%d)' % (' and '.join(FILES), n), n >= 5, str(n))


def commands():
    n = 0
    for line0, block in blocks('README.md'):
        for k, ln in enumerate(block):
            line = line0 + k
            words = shlex.split(ln.split('#')[0]) if ln.strip().startswith('bin/rebond inputs/') else []
            if not words:
                continue
            n += 1
            args = words[1:]
            if '-o' in args:
                i = args.index('-o')
                del args[i:i + 2]
            out = sc.new_dir('readme')
            p = sc.run_limited([sc.REBOND] + args + ['-o', out, '--quiet'], 300, cwd=sc.ROOT, text=True)
            sc.report('README.md:%d: `%s` runs' % (line, ln.strip()), p.returncode == 0,
                      'exit %d: %s' % (p.returncode, p.stderr.strip()[-300:]))
    sc.report('README commands found (%d)' % n, n >= 3, str(n))


def reference_tables():
    """docs/input.md is a reference a newcomer scans (issue 37, item 9): its tables hold syntax,
    defaults and the Cast3M equivalent, no cell over 600 characters (explanations live in
    subsections linked from the row), and every in-page link names an existing heading."""
    text = open(os.path.join(sc.ROOT, 'docs', 'input.md')).read()
    worst, where = 0, ''
    for i, ln in enumerate(text.split('\n'), 1):
        if not ln.startswith('|'):
            continue
        for cell in re.split(r'(?<!\\)\|', ln)[1:-1]:
            if len(cell) > worst:
                worst, where = len(cell), 'line %d' % i
    sc.report('docs/input.md: no table cell over 600 characters', worst <= 600, 'longest %d at %s' % (worst, where))

    def anchor(h):
        h = h.strip().lower()
        h = re.sub(r'[^\w\- ]', '', h)
        return h.replace(' ', '-')
    anchors = {anchor(m.group(1)) for m in re.finditer(r'^#+ (.*)$', text, re.M)}
    links = re.findall(r'\]\(#([^)]+)\)', text)
    bad = [a for a in links if a not in anchors]
    sc.report('docs/input.md: in-page links name existing headings (%d links)' % len(links), links and not bad,
              'missing: %s' % ', '.join(bad))


fragments()
commands()
reference_tables()
