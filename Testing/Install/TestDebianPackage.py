"""Install.DebianPackage: cpack -G DEB builds raymappers_<version>_<arch>.deb, and its file
list (dpkg-deb -c) holds the plugin, its config and the Python package where Debian's
ParaView 5.11 and its Python look (prefix /usr).

usage: TestDebianPackage.py BUILD_DIR OUTPUT_DIR VERSION
"""
import glob
import os
import shutil
import subprocess
import sys

build, out, version = sys.argv[1:4]
shutil.rmtree(out, ignore_errors=True)
os.makedirs(out)
subprocess.run(["cpack", "-G", "DEB", "-B", out, "--config",
                os.path.join(build, "CPackConfig.cmake")], check=True, stdout=subprocess.DEVNULL)
debs = glob.glob(os.path.join(out, "raymappers_%s_*.deb" % version))
assert len(debs) == 1, os.listdir(out)
listing = subprocess.run(["dpkg-deb", "-c", debs[0]], capture_output=True, text=True,
                         check=True).stdout
files = {line.split()[-1].lstrip(".") for line in listing.splitlines()}
wanted = [
    "/usr/bin/paraview.conf",
    "/usr/lib/paraview-plugins/RayMappers.plugins.xml",
    "/usr/lib/paraview-plugins/RayMappers/RayMappers.so",
    "/usr/lib/paraview-plugins/RayMappers/libRayMappersMappers.so",
    "/usr/lib/libRayMappersKernels.so",
    "/usr/lib/python3/dist-packages/raymappers/__init__.py",
    "/usr/lib/python3/dist-packages/raymappers/RayMappersMappers.so",
]
missing = [w for w in wanted if w not in files]
assert not missing, "missing from the package: %s\n%s" % (missing, listing)
info = subprocess.run(["dpkg-deb", "-f", debs[0], "Package", "Version", "Depends"],
                      capture_output=True, text=True, check=True).stdout
print(info)
assert "Package: raymappers" in info and "Version: %s" % version in info, info
for dep in ("paraview", "libembree3-3", "libtbb12"):
    assert dep in info, info
print("PASS", debs[0])
