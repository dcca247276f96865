// The image comparison of every image test (C++ rendering tests, pvpython tests, the GUI
// test): plain C++ over 8-bit RGB, no VTK, so that one definition serves all three doors
// (the C++ tests call it directly, the others through raymappers-compare-images).
//
// For a test image a and its baseline b of the same size, with the per-pixel difference
// d_p = max over R, G, B of |a_p - b_p| (levels of 255):
//   rmse       = sqrt(mean over pixels and channels of (a - b)^2),
//   max error  = max_p d_p,
//   differing  = the fraction of pixels with d_p > tolerance.
// A test passes when rmse <= its rmse threshold, differing <= its differing threshold and the
// max error <= its max-error threshold. Each test's thresholds are measured from its own
// run-to-run noise (Testing/Data/Baseline/thresholds.txt says how) and must make the test
// fail on the perturbations below (a check of the check: raymappers-compare-images
// --perturbations).
#ifndef RayMappers_Test_ImageComparison_h
#define RayMappers_Test_ImageComparison_h

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace raymappers::test
{

/// 8-bit RGB, row-major, rows in the order of the file they came from.
struct RGBImage
{
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb; // 3 * width * height

  std::uint8_t* at(int x, int y) { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
  const std::uint8_t* at(int x, int y) const
  {
    return &rgb[3 * (static_cast<std::size_t>(y) * width + x)];
  }
};

struct ImageDifference
{
  bool sameSize = false;
  double rmse = 0;      // levels of 255
  int maxError = 0;     // levels of 255
  double differing = 0; // fraction of pixels with d_p > tolerance
  int tolerance = 0;
};

struct ImageThresholds
{
  double rmse = 0;
  double differing = 0;
  int tolerance = 0;
  int maxError = 255;
};

ImageDifference compareImages(const RGBImage& test, const RGBImage& baseline, int tolerance);

/// Whether the difference is within the thresholds (always false for different sizes).
bool withinThresholds(const ImageDifference& d, const ImageThresholds& t);

/// One line for a test's log: the measured values against the thresholds and the verdict.
std::string describe(const ImageDifference& d, const ImageThresholds& t);

/// The colour that covers the most pixels (the background of a test picture).
std::array<std::uint8_t, 3> dominantColor(const RGBImage& image);

/// Every pixel moved the fraction f of the way toward the colour c (rounded to nearest).
RGBImage movedToward(const RGBImage& image, const std::array<std::uint8_t, 3>& c, double f);

/// The picture moved by (dx, dy) pixels; the uncovered band repeats the nearest edge.
RGBImage shifted(const RGBImage& image, int dx, int dy);

/// The thresholds table: one line per baseline, "name rmse differing tolerance max_error"
/// ('#' starts a comment). Throws std::runtime_error on a malformed line.
std::map<std::string, ImageThresholds> readThresholdTable(const std::string& path);

}

#endif
