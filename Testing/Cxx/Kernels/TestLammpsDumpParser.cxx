// Unit tests of raymappers::lammps::DumpParser (IO/LAMMPS), the plain C++ kernel of
// vtkLAMMPSDumpReader. Each test writes a small dump by hand into a temporary folder, so the
// expected values follow from the text of the test.
#include "IO/LAMMPS/LammpsDumpParser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#ifdef _WIN32
#include <process.h>
#define RM_GETPID _getpid
#else
#include <unistd.h>
#define RM_GETPID getpid
#endif

namespace fs = std::filesystem;
using raymappers::lammps::buildTimeTable;
using raymappers::lammps::DumpBox;
using raymappers::lammps::DumpFrame;
using raymappers::lammps::DumpParser;
using raymappers::lammps::PositionSource;
using raymappers::lammps::TimeTable;

namespace
{

// A per-test temporary folder, removed at the end.
class LammpsDump : public ::testing::Test
{
protected:
  void SetUp() override
  {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    this->Dir = fs::temp_directory_path() /
                ("raymappers_lammps_" + std::to_string(RM_GETPID()) + "_" + info->name());
    fs::remove_all(this->Dir);
    fs::create_directories(this->Dir);
  }
  void TearDown() override
  {
    std::error_code ec;
    fs::remove_all(this->Dir, ec);
  }
  std::string Write(const std::string& name, const std::string& text)
  {
    const fs::path path = this->Dir / name;
    std::ofstream out(path, std::ios::binary);
    out << text;
    return path.string();
  }
  fs::path Dir;
};

const std::vector<double>* Column(const DumpFrame& frame, const std::string& name)
{
  for (const auto& column : frame.columns)
  {
    if (column.name == name)
    {
      return &column.values;
    }
  }
  return nullptr;
}

bool Contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}

// Two snapshots of an orthogonal periodic box, atoms written out of id order.
const char* const TwoFrames = "ITEM: TIMESTEP\n"
                              "0\n"
                              "ITEM: NUMBER OF ATOMS\n"
                              "3\n"
                              "ITEM: BOX BOUNDS pp pp ff\n"
                              "0.0 10.0\n"
                              "-5.0 5.0\n"
                              "1.0 3.0\n"
                              "ITEM: ATOMS id type x y z vx q\n"
                              "3 2 3.0 0.5 1.5 -0.3 1.0\n"
                              "1 1 1.0 -4.0 2.0 0.1 -1.0\n"
                              "2 1 2.0 4.5 2.5 0.2 0.5\n"
                              "ITEM: TIMESTEP\n"
                              "100\n"
                              "ITEM: NUMBER OF ATOMS\n"
                              "2\n"
                              "ITEM: BOX BOUNDS pp pp ff\n"
                              "0.0 10.0\n"
                              "-5.0 5.0\n"
                              "1.0 3.0\n"
                              "ITEM: ATOMS id type x y z vx q\n"
                              "2 1 2.5 4.0 2.5 0.25 0.5\n"
                              "1 1 1.5 -3.5 2.0 0.15 -1.0\n";

} // namespace

TEST_F(LammpsDump, OrthogonalBoxAndColumns)
{
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("ortho.dump", TwoFrames))) << parser.error();
  EXPECT_TRUE(parser.warnings().empty());
  ASSERT_EQ(parser.numberOfFrames(), 2u);
  const auto& info = parser.frameInfo(0);
  EXPECT_EQ(info.timestep, 0);
  EXPECT_EQ(info.numberOfAtoms, 3);
  EXPECT_FALSE(info.hasTime);
  ASSERT_TRUE(info.box.present);
  EXPECT_EQ(info.box.kind, DumpBox::Shape::Orthogonal);
  EXPECT_TRUE(info.box.isPeriodic(0));
  EXPECT_TRUE(info.box.isPeriodic(1));
  EXPECT_FALSE(info.box.isPeriodic(2));
  EXPECT_EQ(info.box.boundary[2], "ff");
  double bounds[6];
  info.box.bounds(bounds);
  const double expected[6] = { 0.0, 10.0, -5.0, 5.0, 1.0, 3.0 };
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_DOUBLE_EQ(bounds[k], expected[k]) << k;
  }
  EXPECT_EQ(info.columnNames.size(), 7u);

  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  ASSERT_EQ(frame.numberOfAtoms, 3u);
  EXPECT_EQ(frame.positions, PositionSource::Wrapped);
  ASSERT_TRUE(frame.hasIds);
  ASSERT_TRUE(frame.hasTypes);
  // Sorted by id: 1, 2, 3.
  EXPECT_EQ(frame.ids, (std::vector<std::int64_t>{ 1, 2, 3 }));
  EXPECT_EQ(frame.types, (std::vector<std::int32_t>{ 1, 1, 2 }));
  EXPECT_EQ(frame.points, (std::vector<double>{ 1.0, -4.0, 2.0, 2.0, 4.5, 2.5, 3.0, 0.5, 1.5 }));
  // Every column but positions, id and type is an array, in file order.
  ASSERT_EQ(frame.columns.size(), 2u);
  EXPECT_EQ(frame.columns[0].name, "vx");
  EXPECT_EQ(frame.columns[1].name, "q");
  EXPECT_EQ(frame.columns[0].values, (std::vector<double>{ 0.1, 0.2, -0.3 }));
  EXPECT_EQ(frame.columns[1].values, (std::vector<double>{ -1.0, 0.5, 1.0 }));
  EXPECT_TRUE(frame.textColumns.empty());
}

TEST_F(LammpsDump, TwoFramesAndTimeTable)
{
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("two.dump", TwoFrames))) << parser.error();
  ASSERT_EQ(parser.numberOfFrames(), 2u);
  EXPECT_EQ(parser.frameInfo(1).timestep, 100);
  EXPECT_EQ(parser.frameInfo(1).numberOfAtoms, 2);
  EXPECT_EQ(parser.frameInfo(1).headerLine, 13u);
  EXPECT_EQ(parser.frameInfo(1).atomsLine, 22u);

  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(1, frame)) << parser.error();
  EXPECT_EQ(frame.info.timestep, 100);
  ASSERT_EQ(frame.numberOfAtoms, 2u);
  EXPECT_EQ(frame.ids, (std::vector<std::int64_t>{ 1, 2 }));
  EXPECT_EQ(frame.points, (std::vector<double>{ 1.5, -3.5, 2.0, 2.5, 4.0, 2.5 }));
  ASSERT_NE(Column(frame, "vx"), nullptr);
  EXPECT_EQ(*Column(frame, "vx"), (std::vector<double>{ 0.15, 0.25 }));
  // Reading the first snapshot again after the second one gives the same as before.
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.numberOfAtoms, 3u);
  EXPECT_FALSE(parser.readFrame(2, frame));
  EXPECT_TRUE(Contains(parser.error(), "snapshot 3"));

  const TimeTable table = buildTimeTable(parser.frames());
  EXPECT_EQ(table.times, (std::vector<double>{ 0.0, 100.0 }));
  EXPECT_EQ(table.frameForTime(-5.0), 0u);
  EXPECT_EQ(table.frameForTime(0.0), 0u);
  EXPECT_EQ(table.frameForTime(99.5), 0u);
  EXPECT_EQ(table.frameForTime(100.0), 1u);
  EXPECT_EQ(table.frameForTime(1e9), 1u);
  EXPECT_EQ(table.frameForTime(std::nan("")), 0u);
}

TEST_F(LammpsDump, RepeatedTimestepsUseTheLaterSnapshot)
{
  // A run restarted from timestep 100 and appended: timesteps 0 100 200 100 200 300.
  std::string text;
  for (int step : { 0, 100, 200, 100, 200, 300 })
  {
    text += "ITEM: TIMESTEP\n" + std::to_string(step) +
            "\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
            "ITEM: ATOMS id x y z\n1 0.5 0.5 0.5\n";
  }
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("restart.dump", text))) << parser.error();
  ASSERT_EQ(parser.numberOfFrames(), 6u);
  const TimeTable table = buildTimeTable(parser.frames());
  EXPECT_EQ(table.times, (std::vector<double>{ 0, 100, 200, 300 }));
  EXPECT_EQ(table.frames, (std::vector<std::size_t>{ 0, 3, 4, 5 }));
  EXPECT_EQ(table.frameForTime(150.0), 3u);
}

TEST_F(LammpsDump, ScaledCoordinatesOfDumpAtom)
{
  // "dump ... atom" writes id type xs ys zs (scaled to the box), and image flags with
  // dump_modify image yes.
  const std::string text = "ITEM: TIMESTEP\n"
                           "50\n"
                           "ITEM: NUMBER OF ATOMS\n"
                           "2\n"
                           "ITEM: BOX BOUNDS pp pp pp\n"
                           "-2.0 2.0\n"
                           "10.0 20.0\n"
                           "0.0 1.0\n"
                           "ITEM: ATOMS id type xs ys zs ix iy iz\n"
                           "2 1 0.5 0.5 0.5 0 -1 2\n"
                           "1 1 0.0 1.0 0.25 1 0 0\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("atom.dump", text))) << parser.error();
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.positions, PositionSource::Scaled);
  EXPECT_EQ(frame.positionColumns[0], "xs");
  ASSERT_EQ(frame.numberOfAtoms, 2u);
  EXPECT_EQ(frame.ids, (std::vector<std::int64_t>{ 1, 2 }));
  const double expected[6] = { -2.0, 20.0, 0.25, 0.0, 15.0, 0.5 };
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_NEAR(frame.points[k], expected[k], 1e-12) << k;
  }
  ASSERT_NE(Column(frame, "iy"), nullptr);
  EXPECT_EQ(*Column(frame, "iy"), (std::vector<double>{ 0.0, -1.0 }));
}

TEST_F(LammpsDump, PositionPreferenceKeepsOtherTriplesAsArrays)
{
  const std::string text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\n"
                           "ITEM: BOX BOUNDS pp pp pp\n0 2\n0 2\n0 2\n"
                           "ITEM: ATOMS id xu yu zu x y z\n"
                           "7 3.5 0.5 -1.0 1.5 0.5 1.0\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("pref.dump", text))) << parser.error();
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.positions, PositionSource::Wrapped);
  EXPECT_EQ(frame.points, (std::vector<double>{ 1.5, 0.5, 1.0 }));
  ASSERT_NE(Column(frame, "xu"), nullptr);
  EXPECT_EQ(*Column(frame, "xu"), (std::vector<double>{ 3.5 }));
  EXPECT_EQ(Column(frame, "x"), nullptr);
  EXPECT_FALSE(frame.hasTypes);

  // Only unwrapped: they give the positions.
  const std::string unwrapped = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\n"
                                "ITEM: BOX BOUNDS pp pp pp\n0 2\n0 2\n0 2\n"
                                "ITEM: ATOMS id type xu yu zu\n7 1 3.5 0.5 -1.0\n";
  ASSERT_TRUE(parser.open(this->Write("unwrapped.dump", unwrapped))) << parser.error();
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.positions, PositionSource::Unwrapped);
  EXPECT_EQ(frame.points, (std::vector<double>{ 3.5, 0.5, -1.0 }));
}

TEST_F(LammpsDump, TriclinicBox)
{
  // Restricted triclinic cell: xlo=0 xhi=10, ylo=0 yhi=8, zlo=0 zhi=6, xy=2 xz=-1 yz=3.
  // LAMMPS writes the bounding box: xlo_bound = xlo + min(0,xy,xz,xy+xz) = -1,
  // xhi_bound = xhi + max(0,xy,xz,xy+xz) = 12, ylo_bound = 0, yhi_bound = 8 + 3 = 11.
  const std::string text = "ITEM: TIMESTEP\n"
                           "0\n"
                           "ITEM: NUMBER OF ATOMS\n"
                           "2\n"
                           "ITEM: BOX BOUNDS xy xz yz pp pp pp\n"
                           "-1.0 12.0 2.0\n"
                           "0.0 11.0 -1.0\n"
                           "0.0 6.0 3.0\n"
                           "ITEM: ATOMS id type xs ys zs\n"
                           "1 1 0.5 0.5 0.5\n"
                           "2 1 1.0 1.0 1.0\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("tri.dump", text))) << parser.error();
  const DumpBox& box = parser.frameInfo(0).box;
  EXPECT_EQ(box.kind, DumpBox::Shape::Triclinic);
  EXPECT_DOUBLE_EQ(box.tilt[0], 2.0);
  EXPECT_DOUBLE_EQ(box.tilt[1], -1.0);
  EXPECT_DOUBLE_EQ(box.tilt[2], 3.0);
  const double origin[3] = { 0.0, 0.0, 0.0 };
  const double a[3] = { 10.0, 0.0, 0.0 };
  const double b[3] = { 2.0, 8.0, 0.0 };
  const double c[3] = { -1.0, 3.0, 6.0 };
  for (int k = 0; k < 3; ++k)
  {
    EXPECT_DOUBLE_EQ(box.origin[k], origin[k]) << k;
    EXPECT_DOUBLE_EQ(box.A[k], a[k]) << k;
    EXPECT_DOUBLE_EQ(box.B[k], b[k]) << k;
    EXPECT_DOUBLE_EQ(box.C[k], c[k]) << k;
  }
  // The bounding box of the cell is what LAMMPS wrote.
  double bounds[6];
  box.bounds(bounds);
  const double written[6] = { -1.0, 12.0, 0.0, 11.0, 0.0, 6.0 };
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_DOUBLE_EQ(bounds[k], written[k]) << k;
  }
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  // r = origin + xs A + ys B + zs C.
  const double expected[6] = { 5.5, 5.5, 3.0, 11.0, 11.0, 6.0 };
  for (int k = 0; k < 6; ++k)
  {
    EXPECT_NEAR(frame.points[k], expected[k], 1e-12) << k;
  }
}

TEST_F(LammpsDump, GeneralTriclinicBoxTimeAndUnits)
{
  // dump_modify triclinic/general yes units yes time yes.
  const std::string text = "ITEM: UNITS\n"
                           "metal\n"
                           "ITEM: TIME\n"
                           "0.25\n"
                           "ITEM: TIMESTEP\n"
                           "250\n"
                           "ITEM: NUMBER OF ATOMS\n"
                           "1\n"
                           "ITEM: BOX BOUNDS abc origin pp pp fs\n"
                           "2.0 2.0 0.0 1.0\n"
                           "-2.0 2.0 0.0 2.0\n"
                           "0.0 0.0 4.0 3.0\n"
                           "ITEM: ATOMS id type xs ys zs\n"
                           "1 1 0.5 0.5 0.5\n"
                           "ITEM: TIME\n"
                           "0.5\n"
                           "ITEM: TIMESTEP\n"
                           "500\n"
                           "ITEM: NUMBER OF ATOMS\n"
                           "0\n"
                           "ITEM: BOX BOUNDS abc origin pp pp fs\n"
                           "2.0 2.0 0.0 1.0\n"
                           "-2.0 2.0 0.0 2.0\n"
                           "0.0 0.0 4.0 3.0\n"
                           "ITEM: ATOMS id type xs ys zs q\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("general.dump", text))) << parser.error();
  ASSERT_EQ(parser.numberOfFrames(), 2u);
  const auto& info = parser.frameInfo(0);
  EXPECT_EQ(info.units, "metal");
  EXPECT_EQ(parser.frameInfo(1).units, "metal"); // written once, carried forward
  EXPECT_TRUE(info.hasTime);
  EXPECT_DOUBLE_EQ(info.time, 0.25);
  EXPECT_DOUBLE_EQ(parser.frameInfo(1).time, 0.5);
  EXPECT_EQ(info.box.kind, DumpBox::Shape::GeneralTriclinic);
  EXPECT_EQ(info.box.boundary[2], "fs");
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  // origin (1,2,3) + 0.5 (2,2,0) + 0.5 (-2,2,0) + 0.5 (0,0,4) = (1, 4, 5)
  EXPECT_NEAR(frame.points[0], 1.0, 1e-12);
  EXPECT_NEAR(frame.points[1], 4.0, 1e-12);
  EXPECT_NEAR(frame.points[2], 5.0, 1e-12);
  // A snapshot with no atom is valid and keeps its arrays (empty).
  ASSERT_TRUE(parser.readFrame(1, frame)) << parser.error();
  EXPECT_EQ(frame.numberOfAtoms, 0u);
  EXPECT_TRUE(frame.points.empty());
  ASSERT_NE(Column(frame, "q"), nullptr);
}

TEST_F(LammpsDump, UnsortedIdsPermuteEveryColumn)
{
  const std::string text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n5\n"
                           "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                           "ITEM: ATOMS id type element x y z c_pe f_ave[2]\n"
                           "40 2 O 0.4 0.04 0.004 -4 400\n"
                           "10 1 H 0.1 0.01 0.001 -1 100\n"
                           "50 2 O 0.5 0.05 0.005 -5 500\n"
                           "30 1 H 0.3 0.03 0.003 -3 300\n"
                           "20 2 O 0.2 0.02 0.002 -2 200\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("unsorted.dump", text))) << parser.error();
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.ids, (std::vector<std::int64_t>{ 10, 20, 30, 40, 50 }));
  EXPECT_EQ(frame.types, (std::vector<std::int32_t>{ 1, 2, 1, 2, 2 }));
  for (std::size_t i = 0; i < 5; ++i)
  {
    const double k = 0.1 * double(i + 1);
    EXPECT_NEAR(frame.points[3 * i], k, 1e-12);
    EXPECT_NEAR(frame.points[3 * i + 1], k / 10, 1e-12);
    EXPECT_NEAR(frame.points[3 * i + 2], k / 100, 1e-12);
  }
  ASSERT_NE(Column(frame, "c_pe"), nullptr);
  EXPECT_EQ(*Column(frame, "c_pe"), (std::vector<double>{ -1, -2, -3, -4, -5 }));
  ASSERT_NE(Column(frame, "f_ave[2]"), nullptr);
  EXPECT_EQ(*Column(frame, "f_ave[2]"), (std::vector<double>{ 100, 200, 300, 400, 500 }));
  ASSERT_EQ(frame.textColumns.size(), 1u);
  EXPECT_EQ(frame.textColumns[0].name, "element");
  EXPECT_EQ(frame.textColumns[0].values, (std::vector<std::string>{ "H", "O", "H", "O", "O" }));
}

TEST_F(LammpsDump, MissingColumns)
{
  DumpParser parser;
  DumpFrame frame;
  // No coordinates at all: a clear error naming the columns.
  const std::string noPositions = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\n"
                                  "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                                  "ITEM: ATOMS id type vx vy vz\n1 1 0 0 0\n";
  ASSERT_TRUE(parser.open(this->Write("nopos.dump", noPositions))) << parser.error();
  EXPECT_FALSE(parser.readFrame(0, frame));
  EXPECT_TRUE(Contains(parser.error(), "no atom coordinates")) << parser.error();
  EXPECT_TRUE(Contains(parser.error(), "id type vx vy vz")) << parser.error();
  EXPECT_EQ(frame.numberOfAtoms, 0u);

  // Part of a triple.
  const std::string partial = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\n"
                              "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                              "ITEM: ATOMS id x y\n1 0 0\n";
  ASSERT_TRUE(parser.open(this->Write("partial.dump", partial))) << parser.error();
  EXPECT_FALSE(parser.readFrame(0, frame));
  EXPECT_TRUE(Contains(parser.error(), "only part of x y z")) << parser.error();

  // Scaled coordinates without a box cannot be converted.
  const std::string noBox = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\n"
                            "ITEM: ATOMS id xs ys zs\n1 0.5 0.5 0.5\n";
  ASSERT_TRUE(parser.open(this->Write("nobox.dump", noBox))) << parser.error();
  EXPECT_FALSE(parser.readFrame(0, frame));
  EXPECT_TRUE(Contains(parser.error(), "BOX BOUNDS")) << parser.error();

  // No id and no type: file order is kept; no box is fine with unscaled coordinates.
  const std::string noIds = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\n"
                            "ITEM: ATOMS x y z\n2 0 0\n1 0 0\n";
  ASSERT_TRUE(parser.open(this->Write("noids.dump", noIds))) << parser.error();
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_FALSE(frame.hasIds);
  EXPECT_FALSE(frame.hasTypes);
  EXPECT_FALSE(frame.info.box.present);
  EXPECT_EQ(frame.points, (std::vector<double>{ 2, 0, 0, 1, 0, 0 }));
  EXPECT_TRUE(frame.columns.empty());
}

TEST_F(LammpsDump, TruncatedFile)
{
  const std::string full = TwoFrames;
  DumpParser parser;
  DumpFrame frame;

  // Cut inside the atom lines of the second snapshot: the first stays readable, with a
  // warning about the second.
  const std::string cut = full.substr(0, full.size() - 12);
  ASSERT_TRUE(parser.open(this->Write("cut.dump", cut))) << parser.error();
  ASSERT_EQ(parser.numberOfFrames(), 1u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "truncated")) << parser.warnings()[0];
  EXPECT_TRUE(Contains(parser.warnings()[0], "timestep 100")) << parser.warnings()[0];
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.numberOfAtoms, 3u);

  // Cut exactly at a line end inside the second snapshot's atoms.
  const std::string lineCut = full.substr(0, full.rfind("1 1 1.5"));
  ASSERT_TRUE(parser.open(this->Write("linecut.dump", lineCut))) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 1u);
  EXPECT_EQ(parser.warnings().size(), 1u);

  // Cut inside the second snapshot's header.
  const std::string headerCut = full.substr(0, full.find("ITEM: BOX", full.find("100")));
  ASSERT_TRUE(parser.open(this->Write("headercut.dump", headerCut))) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 1u);
  EXPECT_EQ(parser.warnings().size(), 1u);

  // The last line lacks only its newline: nothing is lost, but LAMMPS ends every line with
  // one, so a warning says the last value may have been cut short.
  const std::string noNewline = full.substr(0, full.size() - 1);
  ASSERT_TRUE(parser.open(this->Write("nonewline.dump", noNewline))) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 2u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "line 23")) << parser.warnings()[0];
  ASSERT_TRUE(parser.readFrame(1, frame)) << parser.error();
  EXPECT_EQ(frame.points[0], 1.5);

  // Cut inside the only snapshot: an error, not an empty result.
  const std::string firstCut = full.substr(0, full.find("2 1 2.0"));
  EXPECT_FALSE(parser.open(this->Write("firstcut.dump", firstCut)));
  EXPECT_TRUE(Contains(parser.error(), "truncated")) << parser.error();
  EXPECT_TRUE(Contains(parser.error(), "2 complete atom lines")) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 0u);
}

TEST_F(LammpsDump, EveryPrefixOfAFileIsHandled)
{
  // A file cut at any byte: Open either fails with a message or gives only frames that
  // read cleanly or fail with a message. Never a crash (run under ASan/UBSan too).
  const std::string full = TwoFrames;
  DumpParser parser;
  DumpFrame frame;
  for (std::size_t size = 0; size <= full.size(); ++size)
  {
    const std::string path = this->Write("prefix.dump", full.substr(0, size));
    if (!parser.open(path))
    {
      EXPECT_FALSE(parser.error().empty()) << size;
      continue;
    }
    for (std::size_t i = 0; i < parser.numberOfFrames(); ++i)
    {
      EXPECT_TRUE(parser.readFrame(i, frame)) << size << ": " << parser.error();
    }
  }
}

TEST_F(LammpsDump, CorruptedBytesNeverCrash)
{
  const std::string full = TwoFrames;
  std::mt19937 random(12345);
  std::uniform_int_distribution<std::size_t> position(0, full.size() - 1);
  const char replacements[] = { ' ', '\n', 'x', '-', '.', 'e', '9', '\0', '\r', '+' };
  std::uniform_int_distribution<int> replacement(0, int(sizeof(replacements)) - 1);
  DumpParser parser;
  DumpFrame frame;
  for (int trial = 0; trial < 500; ++trial)
  {
    std::string text = full;
    for (int k = 0; k < 3; ++k)
    {
      text[position(random)] = replacements[replacement(random)];
    }
    if (!parser.open(this->Write("corrupt.dump", text)))
    {
      EXPECT_FALSE(parser.error().empty());
      continue;
    }
    for (std::size_t i = 0; i < parser.numberOfFrames(); ++i)
    {
      if (!parser.readFrame(i, frame))
      {
        EXPECT_FALSE(parser.error().empty());
      }
    }
  }
}

TEST_F(LammpsDump, MalformedFilesGiveClearErrors)
{
  DumpParser parser;
  DumpFrame frame;
  const std::string header = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\n"
                             "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n";

  EXPECT_FALSE(parser.open((this->Dir / "missing.dump").string()));
  EXPECT_TRUE(Contains(parser.error(), "no such file")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("empty.dump", "")));
  EXPECT_TRUE(Contains(parser.error(), "empty")) << parser.error();

  const std::string blank = this->Write("blank.dump", "\n \n");
  EXPECT_FALSE(parser.open(blank));
  EXPECT_EQ(parser.error(),
    "'" + blank + "': the file contains no snapshot ('ITEM: TIMESTEP' ... 'ITEM: ATOMS')");

  EXPECT_FALSE(parser.open(this->Dir.string()));
  EXPECT_TRUE(Contains(parser.error(), "directory")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("data.lmp", "LAMMPS data file\n\n3 atoms\n")));
  EXPECT_TRUE(Contains(parser.error(), "not a LAMMPS text dump")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("dump.gz", std::string("\x1f\x8b\x08\x00rest", 8))));
  EXPECT_TRUE(Contains(parser.error(), "gzip")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("dump.bin", std::string("\x00\x00\x01\x00ITEM", 8))));
  EXPECT_TRUE(Contains(parser.error(), "binary")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("step.dump", "ITEM: TIMESTEP\nabc\n")));
  EXPECT_TRUE(Contains(parser.error(), "line 2")) << parser.error();
  EXPECT_TRUE(Contains(parser.error(), "timestep")) << parser.error();

  EXPECT_FALSE(
    parser.open(this->Write("count.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n-3\n")));
  EXPECT_TRUE(Contains(parser.error(), "number of atoms")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("box.dump",
    "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n0\nITEM: BOX BOUNDS pp pp pp\n0 1\n0\n0 1\n")));
  EXPECT_TRUE(Contains(parser.error(), "line 7")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("order.dump", "ITEM: ATOMS id x y z\n1 0 0 0\n")));
  EXPECT_TRUE(Contains(parser.error(), "before")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("unknown.dump", "ITEM: TIMESTEP\n0\nITEM: BONDS\n")));
  EXPECT_TRUE(Contains(parser.error(), "unknown section")) << parser.error();

  EXPECT_FALSE(parser.open(this->Write("local.dump",
    "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ENTRIES\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 "
    "1\nITEM: ENTRIES index c_1[1]\n1 2\n")));
  EXPECT_TRUE(Contains(parser.error(), "dump local")) << parser.error();

  // More atom lines than NUMBER OF ATOMS, after a complete snapshot: the snapshot is kept,
  // a warning says where the file stops being readable.
  ASSERT_TRUE(parser.open(
    this->Write("extra.dump", header + "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 0 0\n3 0 0 0\n")))
    << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 1u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "line 12")) << parser.warnings()[0];
  EXPECT_TRUE(Contains(parser.warnings()[0], "more atom lines")) << parser.warnings()[0];
  EXPECT_TRUE(Contains(parser.warnings()[0], "ignored")) << parser.warnings()[0];

  // The same damage before any complete snapshot is an error.
  EXPECT_FALSE(parser.open(this->Write("garbage.dump", "ITEM: TIMESTEP\n0\n1 0 0 0\n")));
  EXPECT_TRUE(Contains(parser.error(), "line 3")) << parser.error();

  // Errors found when reading a snapshot name the line and the column.
  ASSERT_TRUE(parser.open(
    this->Write("values.dump", header + "ITEM: ATOMS id type x y z\n1 1 0 0 0\n2 1 0 zero 0\n")))
    << parser.error();
  EXPECT_FALSE(parser.readFrame(0, frame));
  EXPECT_TRUE(Contains(parser.error(), "line 11, column 'y'")) << parser.error();
  EXPECT_TRUE(Contains(parser.error(), "'zero'")) << parser.error();

  ASSERT_TRUE(parser.open(
    this->Write("short.dump", header + "ITEM: ATOMS id type x y z\n1 1 0 0 0\n2 1 0 0\n")))
    << parser.error();
  EXPECT_FALSE(parser.readFrame(0, frame));
  EXPECT_TRUE(Contains(parser.error(), "expected 5 values")) << parser.error();

  ASSERT_TRUE(parser.open(
    this->Write("ids.dump", header + "ITEM: ATOMS id type x y z\n1 1 0 0 0\n2.5 1 0 0 0\n")))
    << parser.error();
  EXPECT_FALSE(parser.readFrame(0, frame));
  EXPECT_TRUE(Contains(parser.error(), "column 'id'")) << parser.error();
  EXPECT_TRUE(Contains(parser.error(), "integer")) << parser.error();
}

TEST_F(LammpsDump, SpecialValuesPassThrough)
{
  // NaN and infinities as printf writes them; '+' signs; CRLF line ends; 1e400 overflows.
  const std::string text = "ITEM: TIMESTEP\r\n0\r\nITEM: NUMBER OF ATOMS\r\n3\r\n"
                           "ITEM: BOX BOUNDS pp pp pp\r\n0 1\r\n0 1\r\n0 1\r\n"
                           "ITEM: ATOMS id type x y z c_s\r\n"
                           "1 1 nan 0 0 -nan\r\n"
                           "2 1 inf -inf +0.5 1e400\r\n"
                           "3 1 +1.5e-1 NaN 1e-400 -1e400\r\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("special.dump", text))) << parser.error();
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_TRUE(std::isnan(frame.points[0]));
  EXPECT_TRUE(std::isinf(frame.points[3]) && frame.points[3] > 0);
  EXPECT_TRUE(std::isinf(frame.points[4]) && frame.points[4] < 0);
  EXPECT_DOUBLE_EQ(frame.points[5], 0.5);
  EXPECT_DOUBLE_EQ(frame.points[6], 0.15);
  EXPECT_TRUE(std::isnan(frame.points[7]));
  EXPECT_EQ(frame.points[8], 0.0);
  const std::vector<double>& s = *Column(frame, "c_s");
  EXPECT_TRUE(std::isnan(s[0]));
  EXPECT_TRUE(std::isinf(s[1]) && s[1] > 0);
  EXPECT_TRUE(std::isinf(s[2]) && s[2] < 0);
}

TEST_F(LammpsDump, LegacyAtomsWithoutColumnNames)
{
  // Old LAMMPS "dump atom": "ITEM: ATOMS" without names, id type xs ys zs [ix iy iz].
  const std::string text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\n"
                           "ITEM: BOX BOUNDS\n0 4\n0 4\n0 4\n"
                           "ITEM: ATOMS\n1 1 0.25 0.5 0.75 0 0 1\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("legacy.dump", text))) << parser.error();
  EXPECT_EQ(parser.frameInfo(0).columnNames.size(), 8u);
  EXPECT_TRUE(parser.frameInfo(0).box.boundary[0].empty());
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.points, (std::vector<double>{ 1.0, 2.0, 3.0 }));
  ASSERT_NE(Column(frame, "iz"), nullptr);
}

TEST_F(LammpsDump, StaleAfterAppendAndLooksLikeDump)
{
  const std::string path = this->Write("grow.dump", TwoFrames);
  EXPECT_TRUE(DumpParser::looksLikeDump(path));
  EXPECT_FALSE(DumpParser::looksLikeDump(this->Write("text.txt", "hello\n")));
  EXPECT_FALSE(DumpParser::looksLikeDump((this->Dir / "none").string()));
  DumpParser parser;
  ASSERT_TRUE(parser.open(path)) << parser.error();
  EXPECT_FALSE(parser.isStale());
  {
    std::ofstream out(path, std::ios::app | std::ios::binary);
    out << "ITEM: TIMESTEP\n200\nITEM: NUMBER OF ATOMS\n0\n"
           "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\nITEM: ATOMS id x y z\n";
  }
  EXPECT_TRUE(parser.isStale());
  ASSERT_TRUE(parser.open(path)) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 3u);

  // A file Open failed on is not stale while it stays as it was (a reader need not index it
  // again, nor report the error again); it is once it appears.
  const std::string later = (this->Dir / "later.dump").string();
  EXPECT_FALSE(parser.open(later));
  EXPECT_FALSE(parser.isStale());
  this->Write("later.dump", TwoFrames);
  EXPECT_TRUE(parser.isStale());
  EXPECT_FALSE(parser.open(this->Write("bad.dump", "ITEM: TIMESTEP\n")));
  EXPECT_FALSE(parser.isStale());
}

TEST_F(LammpsDump, RepeatedColumnNamesAndTypeLabels)
{
  // A column listed twice keeps both arrays (the second gets "_2"); a type column holding
  // type labels instead of numbers becomes a text column.
  const std::string text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\n"
                           "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                           "ITEM: ATOMS id type x y z vx vx id\n"
                           "2 Ow 0.2 0 0 1.0 2.0 20\n"
                           "1 Hw 0.1 0 0 3.0 4.0 10\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("repeat.dump", text))) << parser.error();
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.ids, (std::vector<std::int64_t>{ 1, 2 }));
  EXPECT_FALSE(frame.hasTypes);
  ASSERT_EQ(frame.textColumns.size(), 1u);
  EXPECT_EQ(frame.textColumns[0].name, "type");
  EXPECT_EQ(frame.textColumns[0].values, (std::vector<std::string>{ "Hw", "Ow" }));
  ASSERT_NE(Column(frame, "vx"), nullptr);
  ASSERT_NE(Column(frame, "vx_2"), nullptr);
  ASSERT_NE(Column(frame, "id_2"), nullptr);
  EXPECT_EQ(*Column(frame, "vx"), (std::vector<double>{ 3.0, 1.0 }));
  EXPECT_EQ(*Column(frame, "vx_2"), (std::vector<double>{ 4.0, 2.0 }));
  EXPECT_EQ(*Column(frame, "id_2"), (std::vector<double>{ 10.0, 20.0 }));
}

TEST_F(LammpsDump, CutInTheMiddleOfALineOrANumber)
{
  // A simulation killed while writing stops at any byte. TwoFrames' second snapshot starts
  // at line 13 and its last atom line, line 23, is "1 1 1.5 -3.5 2.0 0.15 -1.0".
  const std::string full = TwoFrames;
  DumpParser parser;
  DumpFrame frame;

  // Cut inside a header line: the first snapshot stays, the warning names the cut line.
  const std::string headerCut = full.substr(0, full.find("ITEM: BOX", 100) + 12);
  ASSERT_TRUE(parser.open(this->Write("headerline.dump", headerCut))) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 1u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "ends in the middle of line 17"))
    << parser.warnings()[0];
  EXPECT_TRUE(Contains(parser.warnings()[0], "'ITEM: BOX BO'")) << parser.warnings()[0];

  // Cut inside an atom line, values missing: the snapshot is dropped with one warning.
  const std::string lineCut = full.substr(0, full.size() - 10);
  ASSERT_TRUE(parser.open(this->Write("atomline.dump", lineCut))) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 1u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "1 complete atom lines"))
    << parser.warnings()[0];
  // The same inside an atom line before the last one: the cut line is not counted.
  const std::string earlyCut = full.substr(0, full.find("2 1 2.5") + 7);
  ASSERT_TRUE(parser.open(this->Write("earlyline.dump", earlyCut))) << parser.error();
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "after 0 complete atom lines"))
    << parser.warnings()[0];

  // Cut inside the last number ("-1." of "-1.0"): every value is there and well formed, so
  // the snapshot is kept, but one warning names the line and the value that may be short.
  const std::string numberCut = full.substr(0, full.size() - 2);
  ASSERT_TRUE(parser.open(this->Write("number.dump", numberCut))) << parser.error();
  EXPECT_EQ(parser.numberOfFrames(), 2u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "line 23")) << parser.warnings()[0];
  EXPECT_TRUE(Contains(parser.warnings()[0], "'-1.'")) << parser.warnings()[0];
  ASSERT_TRUE(parser.readFrame(1, frame)) << parser.error();
  EXPECT_EQ(*Column(frame, "q"), (std::vector<double>{ -1.0, 0.5 }));
}

TEST_F(LammpsDump, MoreOrFewerValuesThanColumnNames)
{
  // Three snapshots of 2 atoms; the second one has a line with a value too many, or too
  // few. That snapshot fails with an error naming the line and both counts; the others read.
  const auto dump = [](const std::string& middleLine)
  {
    std::string text;
    for (int step = 0; step < 3; ++step)
    {
      text += "ITEM: TIMESTEP\n" + std::to_string(step) +
              "\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
              "ITEM: ATOMS id type x y z\n1 1 0.1 0.2 0.3\n" +
              (step == 1 ? middleLine : std::string("2 1 0.4 0.5 0.6")) + "\n";
    }
    return text;
  };
  DumpParser parser;
  DumpFrame frame;
  for (const auto& [line, found] :
    { std::pair<std::string, std::string>{ "2 1 0.4 0.5 0.6 7", "6" }, { "2 1 0.4 0.5", "4" } })
  {
    ASSERT_TRUE(parser.open(this->Write("columns.dump", dump(line)))) << parser.error();
    EXPECT_TRUE(parser.warnings().empty());
    ASSERT_EQ(parser.numberOfFrames(), 3u);
    EXPECT_FALSE(parser.readFrame(1, frame)) << line;
    // Snapshot 2 starts at line 12; its second atom line is line 22.
    EXPECT_TRUE(Contains(parser.error(), "line 22")) << parser.error();
    EXPECT_TRUE(Contains(parser.error(), "expected 5 values (id type x y z), found " + found))
      << parser.error();
    EXPECT_EQ(frame.numberOfAtoms, 0u);
    for (std::size_t good : { 0u, 2u })
    {
      ASSERT_TRUE(parser.readFrame(good, frame)) << parser.error();
      EXPECT_EQ(frame.points, (std::vector<double>{ 0.1, 0.2, 0.3, 0.4, 0.5, 0.6 }));
    }
  }
}

TEST_F(LammpsDump, SnapshotWithTooFewAtomLinesKeepsTheNextOne)
{
  // Three snapshots that each say 2 atoms; one of them has fewer atom lines. Skipping its
  // atom block stops at the next "ITEM:" line instead of counting the next snapshot's header
  // as atoms: that snapshot is dropped with one warning, the others read exactly.
  const auto dump = [](int shortStep, int linesOfShort)
  {
    std::string text;
    for (int step = 0; step < 3; ++step)
    {
      text += "ITEM: TIMESTEP\n" + std::to_string(100 * step) +
              "\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
              "ITEM: ATOMS id x y z\n";
      const int lines = step == shortStep ? linesOfShort : 2;
      for (int a = 1; a <= lines; ++a)
      {
        text +=
          std::to_string(a) + " " + std::to_string(step) + " 0." + std::to_string(a) + " 0.5\n";
      }
    }
    return text;
  };
  DumpParser parser;
  DumpFrame frame;
  // Snapshot k (0-based) starts at line 1 + 11 k when all have 2 atom lines.
  for (const auto& [shortStep, lines, kept, nextHeader] :
    { std::tuple<int, int, std::vector<std::int64_t>, int>{ 1, 1, { 0, 200 }, 22 },
      { 1, 0, { 0, 200 }, 21 },
      { 0, 1, { 100, 200 }, 11 } })
  {
    const std::string what = "snapshot " + std::to_string(shortStep + 1) + " with " +
                             std::to_string(lines) + " atom lines";
    ASSERT_TRUE(parser.open(this->Write("short.dump", dump(shortStep, lines))))
      << what << ": " << parser.error();
    ASSERT_EQ(parser.numberOfFrames(), kept.size()) << what;
    ASSERT_EQ(parser.warnings().size(), 1u) << what;
    const std::string& warning = parser.warnings()[0];
    EXPECT_TRUE(Contains(warning, "timestep " + std::to_string(100 * shortStep))) << warning;
    EXPECT_TRUE(Contains(warning, std::to_string(lines) + " of its 2 atom lines")) << warning;
    EXPECT_TRUE(Contains(warning, "line " + std::to_string(nextHeader))) << warning;
    for (std::size_t i = 0; i < kept.size(); ++i)
    {
      ASSERT_TRUE(parser.readFrame(i, frame)) << what << ": " << parser.error();
      EXPECT_EQ(frame.info.timestep, kept[i]) << what;
      const double x = static_cast<double>(kept[i] / 100);
      EXPECT_EQ(frame.points, (std::vector<double>{ x, 0.1, 0.5, x, 0.2, 0.5 })) << what;
    }
  }
}

TEST_F(LammpsDump, TooFewAtomLinesWhereTheHeaderCrossesTheReadBuffer)
{
  // The index reads the file in blocks of 1 MiB: a header whose "ITEM:" straddles the end of
  // the first block must still stop the skip of a short atom block. The first snapshot's
  // padded atom lines put the second snapshot's "ITEM: TIMESTEP" k bytes before 1 MiB.
  const std::string header = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n";
  const std::string boxAndColumns =
    "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\nITEM: ATOMS id x y z\n";
  const std::string second =
    "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n1\n" + boxAndColumns + "7 0.25 0.5 0.75\n";
  constexpr std::size_t block = std::size_t(1) << 20;
  constexpr std::size_t width = 64; // bytes per atom line, newline included
  DumpParser parser;
  DumpFrame frame;
  for (std::size_t k = 0; k <= 6; ++k)
  {
    // The count line's width is fixed (7 digits), so the atom lines' room is known first.
    const std::size_t room = block - k - header.size() - 8 - boxAndColumns.size();
    const std::size_t lines = room / width;
    std::string atoms;
    for (std::size_t a = 1; a <= lines; ++a)
    {
      std::string line = std::to_string(a) + " 0.1 0.2 0.3";
      const std::size_t size = a == lines ? width + room % width : width;
      atoms += line + std::string(size - 1 - line.size(), ' ') + "\n";
    }
    std::string count = std::to_string(lines + 1); // one atom line too few
    count = std::string(7 - count.size(), '0') + count + "\n";
    const std::string text = header + count + boxAndColumns + atoms + second;
    ASSERT_EQ(text.find("ITEM: TIMESTEP\n100"), block - k);
    ASSERT_TRUE(parser.open(this->Write("boundary.dump", text))) << k << ": " << parser.error();
    ASSERT_EQ(parser.numberOfFrames(), 1u) << k;
    ASSERT_EQ(parser.warnings().size(), 1u) << k;
    EXPECT_TRUE(Contains(parser.warnings()[0],
      std::to_string(lines) + " of its " + std::to_string(lines + 1) + " atom lines"))
      << parser.warnings()[0];
    ASSERT_TRUE(parser.readFrame(0, frame)) << k << ": " << parser.error();
    EXPECT_EQ(frame.info.timestep, 100) << k;
    EXPECT_EQ(frame.points, (std::vector<double>{ 0.25, 0.5, 0.75 })) << k;
  }
}

TEST_F(LammpsDump, DuplicateIdsAreKeptWithOneWarning)
{
  // Ids 3 and 1 occur twice and 5 three times: every atom line is kept (an atom is never
  // dropped silently), sorted by id, equal ids in file order, with one warning that counts
  // the repeated ids.
  const std::string text = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n8\n"
                           "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                           "ITEM: ATOMS id x y z q\n"
                           "3 0.30 0 0 30\n"
                           "5 0.50 0 0 50\n"
                           "1 0.10 0 0 10\n"
                           "3 0.31 0 0 31\n"
                           "2 0.20 0 0 20\n"
                           "5 0.51 0 0 51\n"
                           "1 0.11 0 0 11\n"
                           "5 0.52 0 0 52\n";
  DumpParser parser;
  ASSERT_TRUE(parser.open(this->Write("duplicates.dump", text))) << parser.error();
  DumpFrame frame;
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.numberOfAtoms, 8u);
  EXPECT_EQ(frame.ids, (std::vector<std::int64_t>{ 1, 1, 2, 3, 3, 5, 5, 5 }));
  EXPECT_EQ(*Column(frame, "q"), (std::vector<double>{ 10, 11, 20, 30, 31, 50, 51, 52 }));
  EXPECT_DOUBLE_EQ(frame.points[3 * 4], 0.31);
  ASSERT_EQ(frame.warnings.size(), 1u);
  EXPECT_TRUE(Contains(frame.warnings[0], "3 atom ids occur more than once")) << frame.warnings[0];
  EXPECT_TRUE(Contains(frame.warnings[0], "4 extra atoms")) << frame.warnings[0];
  EXPECT_TRUE(Contains(frame.warnings[0], "id 1 (2 times)")) << frame.warnings[0];
  EXPECT_TRUE(Contains(frame.warnings[0], "timestep 0")) << frame.warnings[0];

  // Already sorted, with a repeat: the same check applies.
  const std::string sorted = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\n"
                             "ITEM: ATOMS id x y z\n1 0 0 0\n2 0 0 0\n2 1 0 0\n";
  ASSERT_TRUE(parser.open(this->Write("sorted.dump", sorted))) << parser.error();
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  ASSERT_EQ(frame.warnings.size(), 1u);
  EXPECT_TRUE(Contains(frame.warnings[0], "1 atom id occurs more than once")) << frame.warnings[0];

  // 200 atoms with ids 1..10, each 20 times, in a scrambled order (more than a sort handles
  // by insertion): q is the file line, so equal ids must come out with increasing q.
  std::string many = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n200\nITEM: ATOMS id x y z q\n";
  for (int line = 0; line < 200; ++line)
  {
    many += std::to_string(1 + (line * 7) % 10) + " 0 0 0 " + std::to_string(line) + "\n";
  }
  ASSERT_TRUE(parser.open(this->Write("many.dump", many))) << parser.error();
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  const std::vector<double>& line = *Column(frame, "q");
  for (std::size_t i = 1; i < 200; ++i)
  {
    ASSERT_LE(frame.ids[i - 1], frame.ids[i]) << i;
    if (frame.ids[i - 1] == frame.ids[i])
    {
      ASSERT_LT(line[i - 1], line[i]) << "id " << frame.ids[i] << " out of file order at " << i;
    }
  }
  ASSERT_EQ(frame.warnings.size(), 1u);
  EXPECT_TRUE(Contains(frame.warnings[0], "10 atom ids occur more than once (190 extra atoms"))
    << frame.warnings[0];

  // Unique ids: no warning.
  ASSERT_TRUE(parser.open(this->Write("unique.dump", TwoFrames))) << parser.error();
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_TRUE(frame.warnings.empty());
}

TEST_F(LammpsDump, AtomCountsTheFileCannotHold)
{
  // NUMBER OF ATOMS beyond 32 bits with a file that holds three atom lines: a clear error
  // naming the count, found from the file size before any line is skipped or any memory is
  // reserved for the atoms.
  DumpParser parser;
  DumpFrame frame;
  const auto dump = [](const std::string& count)
  {
    return "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n" + count +
           "\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
           "ITEM: ATOMS id type x y z\n1 1 0 0 0\n2 1 0 0 0\n3 1 0 0 0\n";
  };
  for (const char* count : { "5000000000", "4294967301", "9223372036854775807" })
  {
    EXPECT_FALSE(parser.open(this->Write("huge.dump", dump(count)))) << count;
    EXPECT_TRUE(Contains(parser.error(), std::string("NUMBER OF ATOMS is ") + count))
      << parser.error();
    // The three atom lines take 30 bytes, and a line at least one.
    EXPECT_TRUE(Contains(parser.error(), "the 30 bytes after line 9 hold at most 30 lines"))
      << parser.error();
    EXPECT_EQ(parser.numberOfFrames(), 0u);
  }

  // The same count in a last snapshot after a complete one: that one stays readable.
  ASSERT_TRUE(parser.open(this->Write("lasthuge.dump", dump("3") + dump("5000000000"))))
    << parser.error();
  ASSERT_EQ(parser.numberOfFrames(), 1u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "NUMBER OF ATOMS is 5000000000"))
    << parser.warnings()[0];
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.numberOfAtoms, 3u);

  // Counts that are not a number of atoms: beyond 64 bits, negative, not integral, text.
  for (const char* count :
    { "99999999999999999999", "1e30", "-1", "-5000000000", "2.5", "nan", "inf", "three", "" })
  {
    EXPECT_FALSE(parser.open(this->Write("notcount.dump", dump(count)))) << count;
    EXPECT_TRUE(Contains(parser.error(),
      "line 4: expected a number of atoms >= 0, found '" + std::string(count) + "'"))
      << parser.error();
  }
}

TEST_F(LammpsDump, GarbageAfterTheHeaderOrTheLastSnapshot)
{
  // Zeros where text should be, as a crash can leave at the end of a file (written sparse:
  // std::filesystem::resize_file extends the file without writing the bytes).
  DumpParser parser;
  DumpFrame frame;
  const std::uintmax_t big = std::uintmax_t(256) << 20;

  // After a header that announces 10 atoms and two atom lines: one "line" of zeros longer
  // than any dump line. The error names the line where it starts (12), after reading at
  // most 64 MiB of it.
  const std::string header = "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n10\n"
                             "ITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\nITEM: ATOMS id x y z\n";
  const std::string headerZeros = this->Write("headerzeros.dump", header + "1 0 0 0\n2 0 0 0\n");
  fs::resize_file(headerZeros, big);
  EXPECT_FALSE(parser.open(headerZeros));
  EXPECT_TRUE(Contains(parser.error(), "line 12 is longer than 64 MiB")) << parser.error();

  // After a complete snapshot shorter than the 4 KiB a file is sniffed with: the snapshot
  // stays readable (the zeros are not taken for a binary file), one warning. (The same with
  // 2 GiB of zeros is IO.TestLAMMPSDumpReader.Garbage2GB.)
  const std::string good = header.substr(0, header.find("10\n")) + "1\n" +
                           header.substr(header.find("ITEM: BOX")) + "1 0.5 0.5 0.5\n";
  const std::string path = this->Write("goodzeros.dump", good);
  fs::resize_file(path, 4096);
  ASSERT_TRUE(parser.open(path)) << parser.error();
  ASSERT_EQ(parser.numberOfFrames(), 1u);
  ASSERT_EQ(parser.warnings().size(), 1u);
  EXPECT_TRUE(Contains(parser.warnings()[0], "line 11 holds NUL bytes"))
    << parser.warnings()[0];
  ASSERT_TRUE(parser.readFrame(0, frame)) << parser.error();
  EXPECT_EQ(frame.points, (std::vector<double>{ 0.5, 0.5, 0.5 }));
}
