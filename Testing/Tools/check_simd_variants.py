#!/usr/bin/env python3
"""Checks that no AVX instruction can run outside the SIMD variants of a kernel library.

With run-time dispatch (Mappers/Common/SimdTarget.h) only the code of the variant namespaces
simd_avx2 and simd_avx512 and CGT's explicitly targeted ray-sphere lanes (Avx2Lanes,
Avx512Lanes) may use VEX or EVEX instructions; every other function of the library is what a
CPU without AVX runs. If the linker had kept an AVX copy of a shared inline function or
template (compiled in a variant's object), that function would show here.

Usage: check_simd_variants.py LIBRARY [OBJDUMP]. Exit 1 and a list of the offending
functions if any, else a count of the wide functions found (there must be some)."""
import re
import subprocess
import sys

ALLOWED = re.compile(r"simd_avx2::|simd_avx512::|Avx2Lanes::|Avx512Lanes::")
# A VEX/EVEX instruction: a mnemonic starting with v (vmovss, vfmadd, vpxor, ...), or any
# operand in a ymm, zmm or mask register; kmov/kand... are AVX-512 mask instructions.
WIDE = re.compile(r"^\s*[0-9a-f]+:\s+(v[a-z0-9]+|k[a-z]+[bwdq])\b|%[yz]mm\d|%k[0-7]\b")


def functions(library, objdump):
    out = subprocess.run([objdump, "-d", "-C", "--no-show-raw-insn", library],
                         check=True, capture_output=True, text=True).stdout
    name, lines = None, []
    for line in out.splitlines():
        m = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
        if m:
            if name:
                yield name, lines
            name, lines = m.group(1), []
        elif name:
            lines.append(line)
    if name:
        yield name, lines


def main():
    library = sys.argv[1]
    objdump = sys.argv[2] if len(sys.argv) > 2 else "objdump"
    wide, bad = 0, []
    for name, lines in functions(library, objdump):
        hits = [l for l in lines if WIDE.search(l)]
        if not hits:
            continue
        if ALLOWED.search(name):
            wide += 1
        else:
            bad.append((name, hits[0].strip()))
    for name, first in bad:
        print(f"AVX outside a SIMD variant: {name}: {first}")
    print(f"{wide} functions of the SIMD variants use AVX; {len(bad)} other functions do")
    return 1 if bad or wide == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
