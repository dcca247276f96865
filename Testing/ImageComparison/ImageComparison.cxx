#include "ImageComparison.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace raymappers::test
{

ImageDifference compareImages(const RGBImage& test, const RGBImage& baseline, int tolerance)
{
  ImageDifference d;
  d.tolerance = tolerance;
  d.sameSize = test.width == baseline.width && test.height == baseline.height &&
               test.rgb.size() == baseline.rgb.size() && !test.rgb.empty();
  if (!d.sameSize)
  {
    return d;
  }
  const std::size_t pixels = test.rgb.size() / 3;
  double squares = 0;
  std::size_t differing = 0;
  for (std::size_t p = 0; p < pixels; ++p)
  {
    int worst = 0;
    for (int c = 0; c < 3; ++c)
    {
      const int e = std::abs(int(test.rgb[3 * p + c]) - int(baseline.rgb[3 * p + c]));
      squares += double(e) * e;
      worst = std::max(worst, e);
    }
    d.maxError = std::max(d.maxError, worst);
    differing += worst > tolerance ? 1 : 0;
  }
  d.rmse = std::sqrt(squares / (3.0 * pixels));
  d.differing = double(differing) / pixels;
  return d;
}

bool withinThresholds(const ImageDifference& d, const ImageThresholds& t)
{
  return d.sameSize && d.tolerance == t.tolerance && d.rmse <= t.rmse &&
         d.differing <= t.differing && d.maxError <= t.maxError;
}

std::string describe(const ImageDifference& d, const ImageThresholds& t)
{
  char line[320];
  if (!d.sameSize)
  {
    std::snprintf(line, sizeof(line), "images differ in size (or are empty): FAIL");
    return line;
  }
  std::snprintf(line,
    sizeof(line),
    "rmse %.4f (<= %.4f), max error %d (<= %d), differing by more than %d: %.4f%% (<= %.4f%%): "
    "%s",
    d.rmse,
    t.rmse,
    d.maxError,
    t.maxError,
    d.tolerance,
    100 * d.differing,
    100 * t.differing,
    withinThresholds(d, t) ? "pass" : "FAIL");
  return line;
}

std::array<std::uint8_t, 3> dominantColor(const RGBImage& image)
{
  std::unordered_map<std::uint32_t, std::size_t> counts;
  std::uint32_t best = 0;
  std::size_t bestCount = 0;
  for (std::size_t p = 0; p + 2 < image.rgb.size(); p += 3)
  {
    const std::uint32_t key = std::uint32_t(image.rgb[p]) << 16 |
                              std::uint32_t(image.rgb[p + 1]) << 8 |
                              std::uint32_t(image.rgb[p + 2]);
    const std::size_t n = ++counts[key];
    if (n > bestCount)
    {
      bestCount = n;
      best = key;
    }
  }
  return { std::uint8_t(best >> 16), std::uint8_t(best >> 8 & 0xFF), std::uint8_t(best & 0xFF) };
}

RGBImage movedToward(const RGBImage& image, const std::array<std::uint8_t, 3>& c, double f)
{
  RGBImage out = image;
  for (std::size_t i = 0; i < out.rgb.size(); ++i)
  {
    const double v = image.rgb[i] + f * (double(c[i % 3]) - image.rgb[i]);
    out.rgb[i] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return out;
}

RGBImage shifted(const RGBImage& image, int dx, int dy)
{
  RGBImage out = image;
  for (int y = 0; y < image.height; ++y)
  {
    const int sy = std::clamp(y - dy, 0, image.height - 1);
    for (int x = 0; x < image.width; ++x)
    {
      const int sx = std::clamp(x - dx, 0, image.width - 1);
      std::copy_n(image.at(sx, sy), 3, out.at(x, y));
    }
  }
  return out;
}

std::map<std::string, ImageThresholds> readThresholdTable(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
  {
    throw std::runtime_error("cannot read the thresholds table " + path);
  }
  std::map<std::string, ImageThresholds> table;
  std::string line;
  int number = 0;
  while (std::getline(in, line))
  {
    ++number;
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    std::string name;
    if (!(words >> name))
    {
      continue;
    }
    ImageThresholds t;
    if (!(words >> t.rmse >> t.differing >> t.tolerance >> t.maxError))
    {
      throw std::runtime_error(path + ":" + std::to_string(number) +
                               ": expected 'name rmse differing tolerance max_error'");
    }
    table[name] = t;
  }
  return table;
}

}
