#!/usr/bin/python3
"""What including lieservo costs an includer's build: the wall time and peak memory of one compiler
invocation (`-c`, one translation unit), per unit, compiler and flag set.

    /usr/bin/python3 benchmarks/compile_time.py                  # the full table (docs/performance.md)
    /usr/bin/python3 benchmarks/compile_time.py --units readme --flags sanitizers   # CI: the slowest build alone

Units (each a consumer's translation unit, compiled against include/):
    readme       tests/build/consumer/main.cpp: the README's loop (filter + servo)
    controllers  benchmarks/compile_time/controllers.cpp: the pushing and dual-arm controllers
    everything   benchmarks/compile_time/everything.cpp: all of lieservo.hpp for SE(3) double and float

Flag sets: -O0 -g, -O2, -O3 -DNDEBUG, -O1 -g -fsanitize=address,undefined (each with -std=c++17);
--flags sanitizers keeps the last alone, the slowest.
Peak memory is the compiler process tree's maximum resident set (wait4's ru_maxrss). A compile
that runs past --timeout is killed and reported as such. Compiles run one at a time, so that
each has the machine to itself. Exit status: 0, or 2 for bad usage or a compile that failed.
"""
from __future__ import annotations

import argparse
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
UNITS = {
    'readme': 'tests/build/consumer/main.cpp',
    'controllers': 'benchmarks/compile_time/controllers.cpp',
    'everything': 'benchmarks/compile_time/everything.cpp',
}
FLAGS = {
    '-O0 -g': ['-O0', '-g'],
    '-O2': ['-O2'],
    '-O3 -DNDEBUG': ['-O3', '-DNDEBUG'],
    '-O1 -g -fsanitize=address,undefined': ['-O1', '-g', '-fsanitize=address,undefined'],
}
COMPILERS = ['g++', 'clang++']


def compile_once(compiler, flags, source, out, timeout):
    """(seconds, peak MiB, 'ok' | 'timeout' | 'failed: …') of one `compiler -c source`."""
    cmd = [compiler, '-std=c++17', *flags, '-I', os.path.join(ROOT, 'include'), '-isystem', '/usr/include/eigen3',
           '-c', source, '-o', out]
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    status = 'ok'
    while True:
        pid, code, usage = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        if time.monotonic() - t0 > timeout:
            os.killpg(p.pid, signal.SIGKILL)
            pid, code, usage = os.wait4(p.pid, 0)
            status = 'timeout'
            break
        time.sleep(0.05)
    seconds = time.monotonic() - t0
    if status == 'ok' and code != 0:
        status = 'failed: ' + p.stderr.read().decode(errors='replace').strip().splitlines()[-1][:200]
    p.stderr.close()
    return seconds, usage.ru_maxrss / 1024.0, status


def compiler_version(compiler):
    first = subprocess.run([compiler, '--version'], capture_output=True, text=True).stdout.splitlines()
    return first[0] if first else compiler


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--units', default=','.join(UNITS), help='comma-separated, from: ' + ', '.join(UNITS))
    ap.add_argument('--compilers', default=','.join(COMPILERS), help='comma-separated compiler commands')
    ap.add_argument('--flags', choices=['all', 'sanitizers'], default='all',
                    help='every flag set (default), or the sanitizer build alone')
    ap.add_argument('--timeout', type=float, default=900, help='seconds before a compile is killed (default 900)')
    args = ap.parse_args(argv)
    units = [u for u in args.units.split(',') if u]
    if not units or any(u not in UNITS for u in units):
        print(f'compile_time.py: --units {args.units}: choose from {", ".join(UNITS)}', file=sys.stderr)
        return 2
    compilers = [c for c in args.compilers.split(',') if c]
    missing = [c for c in compilers if shutil.which(c) is None]
    if not compilers or missing:
        print(f'compile_time.py: compiler not found: {", ".join(missing) or "(none given)"}', file=sys.stderr)
        return 2
    if not (args.timeout > 0):
        print('compile_time.py: --timeout must be > 0', file=sys.stderr)
        return 2

    print(f'machine: {platform.machine()}, {os.cpu_count()} CPU(s); one compile at a time')
    for c in compilers:
        print(f'  {c}: {compiler_version(c)}')
    print(f'{"unit":<12} {"compiler":<9} {"flags":<38} {"wall (s)":>9} {"peak (MiB)":>11}  result')
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        for unit in units:
            source = os.path.join(ROOT, UNITS[unit])
            for c in compilers:
                for name, flags in FLAGS.items():
                    if args.flags == 'sanitizers' and '-fsanitize' not in name:
                        continue
                    s, mib, status = compile_once(c, flags, source, os.path.join(tmp, 'unit.o'), args.timeout)
                    shown = status if status != 'timeout' else f'killed after {args.timeout:g} s'
                    print(f'{unit:<12} {c:<9} {name:<38} {s:9.1f} {mib:11.0f}  {shown}', flush=True)
                    failed |= status.startswith('failed')
    return 2 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
