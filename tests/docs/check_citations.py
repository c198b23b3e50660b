#!/usr/bin/python3
"""Every citation of the paper in the sources and docs names both the paper's number and the
LaTeX label, e.g. "eq. 54 (eqn:se3_normalised_prod_update)", and every label cited is in the
table of docs/math.md ("The paper's labels and their numbers") with that number.

    python3 tests/docs/check_citations.py [REPO_ROOT]     → exit 0, or 1 listing each offence
"""
import os
import re
import subprocess
import sys

LABEL = re.compile(r'(?<![A-Za-z0-9_{])`?((?:eqn|eq|alg|tab|sec):[A-Za-z0-9_]+)`?')
TEXT = re.compile(r'\.(cpp|hpp|py|md|sh|cmake|txt|json)$|CMakeLists')


def label_numbers(math_md: str) -> dict:
    """label → how the sources must name it: 'eq. 54', 'Algorithm 3', 'Section 3.2', 'Appendix A'."""
    table = math_md[math_md.index("## The paper's labels and their numbers"):]
    out = {}
    for m in re.finditer(r'^\| `([a-z]+:[A-Za-z0-9_]+)` \| (.+?) \|$', table, re.M):
        v = m.group(2).strip()
        if v.startswith('('):
            v = 'eq. ' + v[1:-1]
        elif v.startswith('unnumbered'):
            v = 'unnumbered, after eq. ' + re.search(r'after \((\d+)\)', v).group(1)
        elif re.fullmatch(r'Section [A-Z]', v):
            v = 'Appendix ' + v.split()[1]
        out[m.group(1)] = v
    return out


def main(root: str) -> int:
    numbers = label_numbers(open(os.path.join(root, 'docs', 'math.md'), encoding='utf-8').read())
    files = subprocess.run(['git', 'ls-files', 'include', 'examples', 'tests', 'benchmarks', 'docs',
                            'README.md'], cwd=root, capture_output=True, text=True, check=True).stdout.split()
    bad = []
    for f in files:
        if f == 'docs/math.md' or not TEXT.search(f) or f.startswith('tests/docs/'):
            continue
        text = open(os.path.join(root, f), encoding='utf-8', errors='replace').read()
        for m in LABEL.finditer(text):
            line = text.count('\n', 0, m.start()) + 1
            label = m.group(1)
            if label not in numbers:
                bad.append(f'{f}:{line}: {label} is not in docs/math.md')
            elif numbers[label] not in text[max(0, m.start() - 40):m.start()]:
                bad.append(f'{f}:{line}: {label} without "{numbers[label]}" before it')
    for b in bad:
        print(b)
    print(f'{len(bad)} citation(s) without the paper\'s number' if bad else 'all citations carry their numbers')
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else
                  os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))))
