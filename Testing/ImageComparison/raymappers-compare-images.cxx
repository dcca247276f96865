// raymappers-compare-images: the image comparison of ImageComparison.h from the command
// line, for the pvpython and GUI tests (the C++ tests call it directly).
//
//   raymappers-compare-images TEST.png BASELINE.png
//       compares under the baseline's thresholds (thresholds.txt beside it); exit 0 when
//       within them, 1 when not, 2 on an error (a missing file or threshold line).
//   raymappers-compare-images --expect-difference TEST.png BASELINE.png
//       the negative control: exit 0 when the images are NOT within the thresholds.
//   raymappers-compare-images --bound RMSE DIFFERING TOLERANCE MAX_ERROR TEST.png REF.png
//       compares under the thresholds given (an end-to-end test against an independent
//       reference picture, whose measured error the test states); exit 0 within them.
//   raymappers-compare-images --uniform IMAGE.png
//       exit 0 when every pixel has the same colour (an emptied view shows only the
//       background), 1 when not.
//   raymappers-compare-images --measure A.png B.png
//       prints rmse, max error and the differing fraction at tolerances 0 to 4 (for
//       setting thresholds from the measured noise between runs).
//   raymappers-compare-images --perturbations TEST_DIR BASELINE_DIR
//       the check of the check: for every baseline of BASELINE_DIR/thresholds.txt, the
//       test's own output TEST_DIR/<name>.png must pass against the baseline and fail
//       against the baseline made 10% fainter (every pixel 10% of the way to the
//       background, the picture's dominant colour) and shifted by 2 pixels in each of the
//       four directions; exit 0 when all do.
#include "ImageFiles.h"

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

using namespace raymappers::test;

namespace
{
int compareFiles(const std::string& test,
  const std::string& baseline,
  bool expectDifference,
  const ImageThresholds& t)
{
  const ImageDifference d = compareImages(readPNG(test), readPNG(baseline), t.tolerance);
  const bool pass = withinThresholds(d, t);
  std::printf("%s against %s: %s%s\n",
    test.c_str(),
    baseline.c_str(),
    describe(d, t).c_str(),
    expectDifference
      ? (pass ? " (a difference was expected: FAIL)" : " (a difference was expected: ok)")
      : "");
  return pass != expectDifference ? 0 : 1;
}

int checkUniform(const std::string& path)
{
  const RGBImage image = readPNG(path);
  const auto c = dominantColor(image);
  std::size_t others = 0;
  for (std::size_t p = 0; p + 2 < image.rgb.size(); p += 3)
  {
    others += image.rgb[p] != c[0] || image.rgb[p + 1] != c[1] || image.rgb[p + 2] != c[2];
  }
  std::printf("%s: %zu of %zu pixels differ from its dominant colour (%d, %d, %d): %s\n",
    path.c_str(),
    others,
    image.rgb.size() / 3,
    c[0],
    c[1],
    c[2],
    others == 0 ? "uniform" : "not uniform");
  return others == 0 && !image.rgb.empty() ? 0 : 1;
}

int measure(const std::string& a, const std::string& b)
{
  const RGBImage ia = readPNG(a), ib = readPNG(b);
  for (int tolerance = 0; tolerance <= 4; ++tolerance)
  {
    const ImageDifference d = compareImages(ia, ib, tolerance);
    if (!d.sameSize)
    {
      std::printf("%s and %s differ in size\n", a.c_str(), b.c_str());
      return 1;
    }
    std::printf("tolerance %d: rmse %.4f max %d differing %.5f%%\n",
      tolerance,
      d.rmse,
      d.maxError,
      100 * d.differing);
  }
  return 0;
}

int checkPerturbations(const std::string& testDir, const std::string& baselineDir)
{
  const auto table = readThresholdTable(baselineDir + "/thresholds.txt");
  struct Perturbation
  {
    const char* name;
    int dx, dy;
  };
  const std::vector<Perturbation> shifts = { { "shifted +2 x", 2, 0 },
    { "shifted -2 x", -2, 0 },
    { "shifted +2 y", 0, 2 },
    { "shifted -2 y", 0, -2 } };
  int failures = 0;
  for (const auto& [name, t] : table)
  {
    const std::string testPath = testDir + "/" + name + ".png";
    RGBImage test, baseline;
    try
    {
      test = readPNG(testPath);
      baseline = readPNG(baselineDir + "/" + name + ".png");
    }
    catch (const std::exception& e)
    {
      std::printf("FAIL  %s: %s\n", name.c_str(), e.what());
      ++failures;
      continue;
    }
    auto report = [&](const char* what, const RGBImage& b, bool mustPass)
    {
      const ImageDifference d = compareImages(test, b, t.tolerance);
      const bool ok = withinThresholds(d, t) == mustPass;
      std::printf(
        "%s  %-40s %-16s %s\n", ok ? "ok  " : "FAIL", name.c_str(), what, describe(d, t).c_str());
      failures += ok ? 0 : 1;
    };
    report("baseline", baseline, true);
    report("10% fainter", movedToward(baseline, dominantColor(baseline), 0.1), false);
    for (const auto& s : shifts)
    {
      report(s.name, shifted(baseline, s.dx, s.dy), false);
    }
  }
  std::printf("%zu baselines, %d failed check(s)\n", table.size(), failures);
  return failures == 0 && !table.empty() ? 0 : 1;
}
}

int main(int argc, char* argv[])
{
  try
  {
    if (argc == 4 && std::strcmp(argv[1], "--perturbations") == 0)
    {
      return checkPerturbations(argv[2], argv[3]);
    }
    if (argc == 3 && std::strcmp(argv[1], "--uniform") == 0)
    {
      return checkUniform(argv[2]);
    }
    if (argc == 4 && std::strcmp(argv[1], "--measure") == 0)
    {
      return measure(argv[2], argv[3]);
    }
    if (argc == 4 && std::strcmp(argv[1], "--expect-difference") == 0)
    {
      return compareFiles(argv[2], argv[3], true, thresholdsOf(argv[3]));
    }
    if (argc == 8 && std::strcmp(argv[1], "--bound") == 0)
    {
      const ImageThresholds t{
        std::stod(argv[2]), std::stod(argv[3]), std::stoi(argv[4]), std::stoi(argv[5])
      };
      return compareFiles(argv[6], argv[7], false, t);
    }
    if (argc == 3)
    {
      return compareFiles(argv[1], argv[2], false, thresholdsOf(argv[2]));
    }
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "raymappers-compare-images: %s\n", e.what());
    return 2;
  }
  std::fprintf(stderr,
    "usage: raymappers-compare-images [--expect-difference] TEST.png BASELINE.png\n"
    "       raymappers-compare-images --bound RMSE DIFFERING TOLERANCE MAX_ERROR TEST.png REF.png\n"
    "       raymappers-compare-images --uniform IMAGE.png\n"
    "       raymappers-compare-images --measure A.png B.png\n"
    "       raymappers-compare-images --perturbations TEST_DIR BASELINE_DIR\n");
  return 2;
}
