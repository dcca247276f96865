"""Fails when a function of the product code is longer than the limit (issue 28: every
function one phase of its paper, none over 150 lines).

A function is counted from the first line of its signature to its closing brace, as the
project's style writes them: the opening and the closing brace alone on a line, at the
signature's indentation (column 0, or 2 or 4 inside a class). Lambdas count inside the
function that holds them. Class, struct, enum, union and namespace bodies are not functions.

usage: python3 check_function_lengths.py LIMIT FOLDER [FOLDER ...]
Prints the longest functions; exit code 1 when one is over LIMIT lines.
"""
import os
import re
import sys

NOT_FUNCTIONS = re.compile(r'(template\s*<[^>]*>\s*)?(struct|class|namespace|enum|union|extern)\b')


def functions(path):
    """(lines, first line number, signature) of each function in the file."""
    lines = open(path, errors='replace').read().split('\n')
    found = []
    i = 0
    while i < len(lines):
        opening = re.match(r'^( *)\{\s*$', lines[i])
        if opening and len(opening.group(1)) in (0, 2, 4):
            indent = opening.group(1)
            start = i - 1
            while start > 0 and not re.match('^' + indent + r'[A-Za-z~]', lines[start]):
                start -= 1
            signature = lines[start].strip()
            end = i + 1
            while end < len(lines) and not re.match('^' + indent + r'\}', lines[end]):
                end += 1
            if not NOT_FUNCTIONS.match(signature):
                found.append((end - start + 1, start + 1, signature))
                i = end
        i += 1
    return found


def main():
    limit, folders = int(sys.argv[1]), sys.argv[2:]
    counted = []
    for folder in folders:
        for directory, _, names in os.walk(folder):
            for name in names:
                if name.endswith(('.cxx', '.h')):
                    path = os.path.join(directory, name)
                    counted += [(n, path, line, sig) for n, line, sig in functions(path)]
    if not counted:
        print('no functions found in ' + ' '.join(folders))
        return 1
    counted.sort(reverse=True)
    for n, path, line, signature in counted[:5]:
        print('%4d lines  %s:%d  %s' % (n, path, line, signature[:70]))
    over = [c for c in counted if c[0] > limit]
    print('%d functions counted, %d over %d lines' % (len(counted), len(over), limit))
    return 1 if over else 0


if __name__ == '__main__':
    sys.exit(main())
