#!/usr/bin/env python3
"""Write make dependencies between Fortran sources from their `module`, `submodule` and `use` lines.

usage: fdeps.py BUILD_DIR FILE...   (prints rules `BUILD_DIR/a.o: BUILD_DIR/b.o`)
Intrinsic and external modules (iso_*, hdf5, mpi_f08) are ignored.
"""
import os
import re
import sys

build, files = sys.argv[1], sys.argv[2:]
mod_re = re.compile(r'^\s*module\s+(?!(?:procedure|subroutine|function|pure|elemental|recursive)\b)(\w+)', re.I)
sub_re = re.compile(r'^\s*submodule\s*\(\s*(\w+)\s*(?::\s*\w+)?\s*\)', re.I)
use_re = re.compile(r'^\s*use\b(?:\s*,\s*(intrinsic|non_intrinsic))?\s*(?:::)?\s*(\w+)', re.I)
provides, uses = {}, {}
for f in files:
    obj = os.path.join(build, os.path.splitext(os.path.basename(f))[0] + '.o')
    uses[obj] = set()
    with open(f, encoding='utf-8', errors='replace') as fh:
        for line in fh:
            m = mod_re.match(line)
            if m:
                provides[m.group(1).lower()] = obj
            m = sub_re.match(line)       # a submodule depends on its parent module
            if m:
                uses[obj].add(m.group(1).lower())
            m = use_re.match(line)
            if m and (m.group(1) or '').lower() != 'intrinsic':
                uses[obj].add(m.group(2).lower())
for obj in sorted(uses):
    deps = sorted({provides[u] for u in uses[obj] if u in provides and provides[u] != obj})
    if deps:
        print(f"{obj}: {' '.join(deps)}")
