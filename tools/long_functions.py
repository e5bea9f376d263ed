#!/usr/bin/env python3
"""Lists Rust functions longer than a limit (default 60 lines), signature to closing brace.

Usage: tools/long_functions.py [--limit N] [--tests] [PATH ...]   (default PATH: src)
Test modules (`mod tests`, files under tests/ or named tests.rs) are left out unless --tests.
"""
import re
import sys
from pathlib import Path

FN = re.compile(r'^\s*(pub(\([^)]*\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?(extern\s+"[^"]*"\s+)?fn\s+(\w+)')


def strip(line, state):
    """Removes comments, strings and char literals; `state` carries block comments and strings across lines."""
    out, i, n = [], 0, len(line)
    while i < n:
        if state['block']:
            j = line.find('*/', i)
            if j < 0:
                return ''.join(out)
            state['block'] = False
            i = j + 2
        elif line.startswith('//', i):
            break
        elif line.startswith('/*', i):
            state['block'] = True
            i += 2
        elif state['string'] or line[i] == '"':
            # a string may run over several lines (`\` continuations, literal newlines)
            j = i if state['string'] else i + 1
            while j < n and line[j] != '"':
                j += 2 if line[j] == '\\' else 1
            state['string'] = j >= n
            i = j + 1
        elif line[i] == "'" and re.match(r"'(\\.|[^\\'])'", line[i:i + 4]):
            i += len(re.match(r"'(\\.|[^\\'])'", line[i:i + 4]).group(0))
        else:
            out.append(line[i])
            i += 1
    return ''.join(out)


def functions(path):
    lines = path.read_text(errors='replace').splitlines()
    state = {'block': False, 'string': False}
    code = [strip(l, state) for l in lines]
    test_depth = None
    depth = 0
    found = []
    i = 0
    while i < len(code):
        line = code[i]
        if test_depth is None and re.match(r'\s*mod\s+tests\b', line) and i > 0 and 'cfg(test)' in lines[i - 1]:
            test_depth = depth
        m = FN.match(line)
        if m and test_depth is None:
            # find the body's opening brace (or a `;` for a declaration without body)
            j, d, opened = i, 0, False
            while j < len(code):
                for ch in code[j]:
                    if ch == '{':
                        d += 1
                        opened = True
                    elif ch == '}':
                        d -= 1
                    elif ch == ';' and not opened and d == 0:
                        break
                if opened and d == 0:
                    break
                if not opened and ';' in code[j]:
                    break
                j += 1
            if opened:
                found.append((j - i + 1, m.group(7), i + 1))
        for ch in line:
            if ch == '{':
                depth += 1
            elif ch == '}':
                depth -= 1
                if test_depth is not None and depth == test_depth:
                    test_depth = None
        i += 1
    return found


def main(argv):
    limit, tests, paths = 60, False, []
    it = iter(argv)
    for a in it:
        if a == '--limit':
            limit = int(next(it))
        elif a == '--tests':
            tests = True
        else:
            paths.append(a)
    files = []
    for p in paths or ['src']:
        p = Path(p)
        files += [p] if p.is_file() else sorted(p.rglob('*.rs'))
    rows = []
    for f in files:
        if not tests and (f.name == 'tests.rs' or 'tests' in f.parts[:-1]):
            continue
        rows += [(n, f'{f}:{line}', name) for n, name, line in functions(f) if n > limit]
    for n, where, name in sorted(rows, reverse=True):
        print(f'{n:5}  {where}  {name}')
    print(f'{len(rows)} functions over {limit} lines')


if __name__ == '__main__':
    main(sys.argv[1:])
