"""Fails when a file includes a kernel header (a header not named vtk* in a kernel folder)
by its bare name: kernel headers are included path-prefixed from the source root
("Mappers/CGT/SphereSet.h"), so the name says the method and no consumer depends on a
bare "Frame.h" that any other library could also ship (issue 28, modules).

usage: python3 check_kernel_includes.py SOURCE_ROOT
Prints each offending include; exit code 1 when there is one.
"""
import os
import re
import sys

KERNEL_FOLDERS = ["Mappers/Common", "Mappers/CGT", "Mappers/RBF", "Mappers/ZSweep",
                  "Mappers/SPH", "IO/LAMMPS"]
SCANNED = ["Mappers", "Filters", "IO", "Plugin", "Testing", "Examples"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def main(root):
    kernel_headers = set()
    for folder in KERNEL_FOLDERS:
        for name in os.listdir(os.path.join(root, folder)):
            if name.endswith(".h") and not name.startswith("vtk"):
                kernel_headers.add(name)
    bad = []
    for top in SCANNED:
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            for name in files:
                if not name.endswith((".h", ".cxx", ".cpp", ".hpp")):
                    continue
                path = os.path.join(dirpath, name)
                for number, line in enumerate(open(path, errors="replace"), 1):
                    m = INCLUDE.match(line)
                    if m and m.group(1) in kernel_headers:
                        bad.append(f"{os.path.relpath(path, root)}:{number}: #include \"{m.group(1)}\"")
    for line in bad:
        print(line)
    print(f"{len(kernel_headers)} kernel headers; {len(bad)} bare includes of them")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
