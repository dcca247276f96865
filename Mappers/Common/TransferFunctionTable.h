// A transfer function sampled into a table: RGBA at n evenly spaced scalar values over
// [lo, hi], looked up with linear interpolation between samples and clamped outside.
//
// Opacity in a volume property is given per `unitDistance` of path length (VTK's scalar
// opacity unit distance): an opacity alpha over the unit distance means an extinction
// tau = -ln(1 - alpha) / unitDistance, so a segment of length dt has opacity
//   alpha(dt) = 1 - (1 - alpha)^(dt / unitDistance).
#ifndef RayMappers_TransferFunctionTable_h
#define RayMappers_TransferFunctionTable_h

#include <array>
#include <vector>

namespace raymappers
{

class TransferFunctionTable
{
public:
  /// `rgba`: n samples of 4 floats (straight, not premultiplied, colour and opacity)
  /// taken at lo + k (hi - lo)/(n - 1). n >= 1; lo == hi is allowed (a constant table).
  void assign(std::vector<float> rgba, double lo, double hi, double unitDistance = 1.0);

  int size() const { return static_cast<int>(Samples.size() / 4); }
  double rangeMin() const { return Lo; }
  double rangeMax() const { return Hi; }
  double unitDistance() const { return UnitDistance; }
  bool empty() const { return Samples.empty(); }

  /// Interpolated RGBA at scalar value v (clamped to the range; NaN gives transparent
  /// black, never NaN).
  std::array<float, 4> lookup(double v) const;

  /// Opacity of a segment of length dt whose opacity per unit distance is alpha.
  static double correctOpacity(double alpha, double dt, double unitDistance);

private:
  std::vector<float> Samples;
  double Lo = 0, Hi = 1, UnitDistance = 1;
  double Scale = 0; // (n - 1) / (hi - lo), 0 for a constant table
};

} // namespace raymappers

#endif
