"""pvpython: the plugin's LAMMPS dump reader as a ParaView user meets it.

Without --case: a real dump opens through ParaView's reader factory, with its atoms,
arrays and time steps, and shows as ray-traced spheres.

With --case NAME FOLDER: bad input written into FOLDER (the 2 GiB garbage files of
Garbage2GB are written there by the WriteGarbage fixture of the C++ test), opened with
OpenDataFile or, where ParaView's factory refuses the file, with the reader's proxy
LAMMPSDumpReader(FileNames=...). Every message that reaches VTK's output window is
counted: each problem gives exactly one, naming it, and the readable snapshots read
exactly (checked on the client-side output of the reader).

usage: pvpython TestLAMMPSReaderPlugin.py PLUGIN.so DUMP
       pvpython TestLAMMPSReaderPlugin.py PLUGIN.so --case NAME FOLDER
"""
import math
import os
import sys
import time

from paraview.simple import (  # noqa: E402
    Delete, GetActiveViewOrCreate, LoadPlugin, OpenDataFile, Render, Show)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from raymappers_testing import OutputWindowMessages, check, failures  # noqa: E402

plugin = sys.argv[1]
LoadPlugin(plugin, remote=False, ns=globals())


def real_dump(dump):
    reader = OpenDataFile(dump)
    check(reader is not None and reader.GetXMLName() == "LAMMPSDumpReader",
          "the reader factory picks the LAMMPS dump reader for .dump")
    reader.UpdatePipeline(0.0)
    info = reader.GetDataInformation()
    check(info.GetNumberOfPoints() == 256, "256 atoms at step 0")
    check(list(reader.TimestepValues) == [0.0, 100.0], "time steps 0 and 100")
    arrays = [reader.PointData.GetArray(i).GetName() for i in range(len(reader.PointData))]
    check("type" in arrays and "vx" in arrays, "point arrays type and vx")

    view = GetActiveViewOrCreate("RenderView")
    display = Show(reader, view)
    display.SetRepresentationType("Ray-Traced Spheres")
    display.Radius = 0.4
    Render(view)
    check(display.GetProperty("Radius") is not None, "shown as Ray-Traced Spheres")
    Delete(view)


# -- bad input -------------------------------------------------------------------------

class Messages(OutputWindowMessages):
    """What reaches VTK's output window inside the block: the errors and warnings of every
    object (pvpython sends print() there too, so the block prints nothing)."""

    def describe(self):
        return "".join("\n      error: " + e for e in self.errors) + \
            "".join("\n      warning: " + w for w in self.warnings)

    def expect_one(self, error, parts, what):
        kind = self.errors if error else self.warnings
        named = len(kind) == 1 and all(part in kind[0] for part in parts)
        ok = self.count == 1 and named
        check(ok, "%s: exactly one %s naming %r%s" % (
            what, "error" if error else "warning", parts[0], "" if ok else self.describe()))


def atom_line(atom, step):
    """Atom `atom` of the snapshot at `step`: at (atom, step / 100, 0.5), q = 10 atom + step / 100."""
    return "%d 1 %d %d 0.5 %d" % (atom, atom, step // 100, 10 * atom + step // 100)


def snapshot(step, atoms=3, count=None):
    """A snapshot written in reverse id order: 12 lines for 3 atoms, atom lines 10 to 12."""
    text = ("ITEM: TIMESTEP\n%d\nITEM: NUMBER OF ATOMS\n%s\nITEM: BOX BOUNDS pp pp pp\n"
            "0 10\n0 10\n0 10\nITEM: ATOMS id type x y z q\n") % (
                step, count if count is not None else str(atoms))
    return text + "".join(atom_line(a, step) + "\n" for a in range(atoms, 0, -1))


THREE_STEPS = snapshot(0) + snapshot(100) + snapshot(200)


def write(folder, name, text):
    path = os.path.join(folder, name)
    with open(path, "wb") as f:
        f.write(text.encode("latin-1"))
    return path


def time_steps(reader):
    values = reader.TimestepValues
    if values is None:
        return []
    return list(values) if hasattr(values, "__len__") else [values]


def output(reader, t):
    """The reader's output at time t, as the client-side object holds it (builtin session)."""
    reader.UpdatePipeline(t)
    return reader.GetClientSideObject().GetOutputDataObject(0)


def holds_snapshot(data, step, atoms=3):
    """True if data holds snapshot(step)'s atoms exactly, sorted by id."""
    q = data.GetPointData().GetArray("q")
    ids = data.GetPointData().GetArray("id")
    if data.GetNumberOfPoints() != atoms or q is None or ids is None:
        return False
    for i in range(atoms):
        if (ids.GetTuple1(i) != i + 1 or data.GetPoint(i) != (i + 1, step // 100, 0.5)
                or q.GetTuple1(i) != 10 * (i + 1) + step // 100):
            return False
    return True


def read_all_steps(reader, good, what):
    """Every step twice, as an animation going back and forth; the good ones read exactly."""
    for _ in range(2):
        for step in (0, 100, 200):
            data = output(reader, step)
            if step in good:
                check(holds_snapshot(data, step), "%s: timestep %d reads exactly" % (what, step))


def reader_proxy(path):
    """The reader's own proxy, for a file ParaView's factory (OpenDataFile) refuses."""
    return LAMMPSDumpReader(FileNames=[path])  # noqa: F821 (defined by LoadPlugin)


def truncated(folder):
    full = THREE_STEPS
    third = full.find("ITEM: TIMESTEP\n200")
    # The third snapshot starts at line 25; its atom lines are 34 (id 3), 35 and 36 (id 1).
    cuts = [
        ("in the header", full.find("3\n", full.find("NUMBER OF ATOMS", third)),
         ["ends after 'ITEM: NUMBER OF ATOMS' at line 27"]),
        ("in a header line", full.find("UNDS", third),
         ["ends in the middle of line 29", "'ITEM: BOX BO'"]),
        ("in the ATOMS block", full.find(atom_line(2, 200), third),
         ["timestep 200", "is truncated: it has 3 atoms", "after 1 complete atom lines"]),
        ("in an atom line", full.find(atom_line(2, 200), third) + 5,
         ["timestep 200", "after 1 complete atom lines"]),
    ]
    for name, size, parts in cuts:
        what = "cut " + name
        with Messages() as log:
            reader = OpenDataFile(write(folder, "cut_%d.dump" % size, full[:size]))
            check(time_steps(reader) == [0.0, 100.0], what + ": time steps 0 and 100")
            read_all_steps(reader, (0, 100), what)
        log.expect_one(False, parts, what)
        Delete(reader)

    what = "cut in a number"
    with Messages() as log:
        reader = OpenDataFile(write(folder, "number.dump", full[:-2]))
        check(time_steps(reader) == [0.0, 100.0, 200.0], what + ": 3 time steps")
        read_all_steps(reader, (0, 100), what)
        q = output(reader, 200).GetPointData().GetArray("q")
        check(q is not None and q.GetTuple1(0) == 1.0 and q.GetTuple1(2) == 32.0,
              what + ": timestep 200 read as the file has it")
    log.expect_one(False, ["line 36", "'1' may have been cut short"], what)
    Delete(reader)

    what = "cut in the first snapshot"
    with Messages() as log:
        reader = OpenDataFile(write(folder, "first.dump", full[:full.find("ITEM: BOX")]))
        check(output(reader, 0).GetNumberOfPoints() == 0 and time_steps(reader) == [],
              what + ": no time step, empty output")
    log.expect_one(True, ["the file ends in the header of the snapshot at line 1"], what)
    Delete(reader)

    # A series of one-snapshot files (dump ... dump.*) whose last file is being written: the
    # others read; the reader's one error, and ParaView's file series reader adds its own
    # warning that the file has no time (that one is ParaView's, not the reader's).
    what = "series with a cut last file"
    files = [write(folder, "series.%d.dump" % step, snapshot(step)) for step in (0, 100)]
    files.append(write(folder, "series.200.dump", snapshot(200)[:-12]))
    with Messages() as log:
        reader = OpenDataFile(files)
        check(time_steps(reader) == [0.0, 100.0], what + ": time steps 0 and 100")
        read_all_steps(reader, (0, 100), what)
    ours = [e for e in log.errors if "series.200.dump" in e and "is truncated" in e]
    theirs = [w for w in log.warnings if "Input with index 2 has no time information" in w]
    ok = log.count == 2 and len(ours) == 1 and len(theirs) == 1
    check(ok, what + ": one error naming the file, ParaView's one warning" +
          ("" if ok else log.describe()))
    Delete(reader)


def extra_columns(folder):
    line = atom_line(2, 100)  # line 23: snapshot 2 (timestep 100) starts at line 13
    for changed, found in ((line + " 7", "7"), (line[:7], "4")):
        what = found + " values on a line"
        with Messages() as log:
            reader = OpenDataFile(write(folder, "columns%s.dump" % found,
                                        THREE_STEPS.replace(line, changed)))
            check(time_steps(reader) == [0.0, 100.0, 200.0], what + ": 3 time steps")
            read_all_steps(reader, (0, 200), what)
            check(output(reader, 100).GetNumberOfPoints() == 0, what + ": timestep 100 is empty")
        log.expect_one(True, ["line 23: expected 6 values (id type x y z q), found " + found,
                              "timestep 100"], what)
        Delete(reader)


def duplicate_ids(folder):
    second = ("ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n6\nITEM: BOX BOUNDS pp pp pp\n"
              "0 10\n0 10\n0 10\nITEM: ATOMS id type x y z q\n"
              "4 1 4.0 1 0.5 41\n2 1 2.0 1 0.5 21\n1 1 1.0 1 0.5 11\n"
              "2 1 2.5 1 0.5 22\n3 1 3.0 1 0.5 31\n4 1 4.5 1 0.5 42\n")
    with Messages() as log:
        reader = OpenDataFile(write(folder, "duplicates.dump", snapshot(0) + second))
        for _ in range(2):
            check(holds_snapshot(output(reader, 0), 0), "timestep 0 (unique ids) reads exactly")
            data = output(reader, 100)
            ids = data.GetPointData().GetArray("id")
            q = data.GetPointData().GetArray("q")
            kept = data.GetNumberOfPoints() == 6 and [
                (ids.GetTuple1(i), data.GetPoint(i)[0], q.GetTuple1(i)) for i in range(6)] == [
                (1, 1.0, 11), (2, 2.0, 21), (2, 2.5, 22), (3, 3.0, 31), (4, 4.0, 41),
                (4, 4.5, 42)]
            check(kept, "repeated ids: all 6 atoms kept, sorted by id, equal ids in file order")
    log.expect_one(False, ["2 atom ids occur more than once (2 extra atoms: id 2 (2 times), "
                           "id 4 (2 times))", "timestep 100"], "repeated ids")
    Delete(reader)

    # In a file series ParaView's file series reader gives the reader another file name at
    # every change of file, so each file is indexed again: its warnings still come once.
    what = "series, animated back and forth"
    files = [write(folder, "series.0.dump", snapshot(0)),
             write(folder, "series.100.dump", snapshot(0).replace("TIMESTEP\n0", "TIMESTEP\n100")
                   .replace("\n2 1 2 0 0.5 20\n", "\n1 1 2 0 0.5 20\n")),
             write(folder, "series.200.dump", snapshot(200)[:-1])]
    with Messages() as log:
        reader = OpenDataFile(files)
        for step in (0, 100, 200, 0, 100, 200, 100):
            output(reader, step)
        check(holds_snapshot(output(reader, 0), 0), what + ": timestep 0 reads exactly")
    repeated = [w for w in log.warnings if "series.100.dump" in w and "id 1 (2 times)" in w]
    cut = [w for w in log.warnings if "series.200.dump" in w and "without a newline" in w]
    ok = log.count == 2 and len(repeated) == 1 and len(cut) == 1
    check(ok, what + ": one warning per file" + ("" if ok else log.describe()))
    Delete(reader)


def atom_count_overflow(folder):
    for count in ("5000000000", "4294967301"):
        with Messages() as log:
            reader = OpenDataFile(write(folder, "huge%s.dump" % count, snapshot(0, 3, count)))
            check(output(reader, 0).GetNumberOfPoints() == 0, count + " atoms: empty output")
        log.expect_one(True, ["NUMBER OF ATOMS is " + count, "bytes after line 9 hold at most"],
                       count + " atoms")
        Delete(reader)
    what = "2^32+5 atoms in the last snapshot"
    with Messages() as log:
        reader = OpenDataFile(write(folder, "lasthuge.dump", snapshot(0) + snapshot(100) +
                                    snapshot(200, 3, "4294967301")))
        check(time_steps(reader) == [0.0, 100.0], what + ": time steps 0 and 100")
        read_all_steps(reader, (0, 100), what)
    log.expect_one(False, ["NUMBER OF ATOMS is 4294967301", "timestep 200"], what)
    Delete(reader)
    for index, count in enumerate(("-7", "-5000000000", "99999999999999999999", "1e30", "nan",
                                   "three")):
        with Messages() as log:
            reader = OpenDataFile(write(folder, "count%d.dump" % index, snapshot(0, 3, count)))
            check(output(reader, 0).GetNumberOfPoints() == 0, "count %r: empty output" % count)
        log.expect_one(True, ["line 4: expected a number of atoms >= 0, found '%s'" % count],
                       "count %r" % count)
        Delete(reader)


def special_values(folder):
    path = write(folder, "special.dump",
                 "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n4\nITEM: BOX BOUNDS pp pp pp\n"
                 "0 10\n0 10\n0 10\nITEM: ATOMS id type x y z q\n"
                 "1 1 nan 0 -nan -nan\n2 1 inf -inf 0 inf\n3 1 1e39 -1e39 1e400 1e-400\n"
                 "4 1 1 2 3 4\n")
    inf = float("inf")
    for precision, name in ((0, "single"), (1, "double")):
        with Messages() as log:
            reader = OpenDataFile(path)
            reader.OutputPointsPrecision = precision
            data = output(reader, 0)
            q = data.GetPointData().GetArray("q")
            points = [data.GetPoint(i) for i in range(data.GetNumberOfPoints())]
        check(len(points) == 4 and q is not None, name + ": all 4 atoms, NaN ones included")
        if len(points) == 4 and q is not None:
            check(math.isnan(points[0][0]) and points[0][1] == 0 and math.isnan(points[0][2]),
                  name + ": NaN passed on")
            check(points[1][:2] == (inf, -inf), name + ": infinities passed on")
            check(points[2][:2] == ((inf, -inf) if precision == 0 else (1e39, -1e39)),
                  name + ": 1e39 is " + ("infinite in float" if precision == 0 else "kept"))
            check(points[2][2] == inf and points[3] == (1, 2, 3),
                  name + ": 1e400 is infinite, the finite atom exact")
            check(math.isnan(q.GetTuple1(0)) and [q.GetTuple1(i) for i in (1, 2, 3)] ==
                  [inf, 0.0, 4.0], name + ": values NaN, inf, 0 (1e-400), 4 passed on")
        if precision == 0:
            log.expect_one(False, ["2 coordinates are beyond the range of float"], name)
        else:
            check(log.count == 0, name + ": no message" + ("" if log.count == 0 else log.describe()))
        Delete(reader)


def output_points_precision(folder):
    path = write(folder, "good.dump", THREE_STEPS)
    for precision in (-1, 3, 2 ** 31 - 1):
        what = "OutputPointsPrecision %d" % precision
        with Messages() as log:
            reader = OpenDataFile(path)
            reader.OutputPointsPrecision = precision
            read_all_steps(reader, (0, 100, 200), what)
            single = output(reader, 0).GetPoints().GetDataType() == 10  # VTK_FLOAT
        check(single, what + ": single precision")
        log.expect_one(False, [what + " is none of"], what)
        Delete(reader)


def not_a_dump(folder):
    files = [
        (os.path.join(folder, "missing.dump"), "no such file"),
        (write(folder, "empty.dump", ""), "is empty"),
        (write(folder, "blank.dump", "\n  \n\n"), "contains no snapshot"),
        (write(folder, "data.dump", "LAMMPS data file\n\n3 atoms\n"),
         "is not a LAMMPS text dump"),
        (write(folder, "binary.dump", "\x7fELF\0\0\x01"), "is a binary file"),
        (write(folder, "dump.gz.dump", "\x1f\x8b\x08\x00"), "gzip-compressed"),
    ]
    for path, named in files:
        what = repr(os.path.basename(path))
        # ParaView's factory refuses these files itself, before any reader runs.
        with Messages() as log:
            try:
                OpenDataFile(path)
                refused = ""
            except RuntimeError as e:
                refused = str(e)
        check(path in refused and log.count == 0,
              what + ": OpenDataFile refuses it (%r), no VTK message" % refused)
        # The reader's own proxy reads it, with one error naming the problem.
        with Messages() as log:
            reader = reader_proxy(path)
            for step in (0, 100, 0):
                data = output(reader, step)
            empty = data.GetNumberOfPoints() == 0
        check(empty, what + ": LAMMPSDumpReader gives an empty output")
        log.expect_one(True, [named], what)
        Delete(reader)


def garbage_2gb(folder):
    """The 2 GiB files of the WriteGarbage fixture; the times are printed, not asserted."""
    cases = [
        ("zeros.dump", True, ["is a binary file"]),
        ("random.dump", True, ["is a binary file"]),
        ("header-zeros.dump", True, ["line 12 is longer than 64 MiB"]),
        ("count-zeros.dump", True, ["NUMBER OF ATOMS is 5000000000", "hold at most"]),
        ("good-zeros.dump", False, ["line 13 is longer than 64 MiB", "after snapshot 1"]),
    ]
    for name, error, parts in cases:
        path = os.path.join(folder, name)
        if not os.path.exists(path) or os.path.getsize(path) != 2 << 30:
            check(False, path + " is 2 GiB (written by the WriteGarbage fixture)")
            continue
        start = time.perf_counter()
        with Messages() as log:
            try:
                reader = OpenDataFile(path)
            except RuntimeError:  # the factory's sniffing refuses the binary ones
                reader = reader_proxy(path)
            data = output(reader, 0)
        seconds = time.perf_counter() - start
        print("%-18s opened and read in %.3f s" % (name, seconds))
        log.expect_one(error, parts, name)
        check(holds_snapshot(data, 0) if not error else data.GetNumberOfPoints() == 0,
              name + (": snapshot 1 reads" if not error else ": empty output"))
        Delete(reader)


CASES = {
    "Truncated": truncated,
    "ExtraColumns": extra_columns,
    "DuplicateIds": duplicate_ids,
    "AtomCountOverflow": atom_count_overflow,
    "SpecialValues": special_values,
    "OutputPointsPrecision": output_points_precision,
    "NotADump": not_a_dump,
    "Garbage2GB": garbage_2gb,
}

if sys.argv[2] == "--case":
    case, folder = sys.argv[3], sys.argv[4]
    os.makedirs(folder, exist_ok=True)
    CASES[case](folder)
else:
    real_dump(sys.argv[2])

if failures:
    sys.exit(1)
print("all checks passed")
