// PNG files and render windows as the RGBImage of ImageComparison.h (through VTK's PNG
// reader and writer), and the baseline check of the C++ rendering tests.
#ifndef RayMappers_Test_ImageFiles_h
#define RayMappers_Test_ImageFiles_h

#include "ImageComparison.h"

#include <string>

class vtkImageData;
class vtkRenderWindow;

namespace raymappers::test
{

/// The RGB of a PNG file (rows bottom to top, as VTK reads them); throws
/// std::runtime_error when the file cannot be read.
RGBImage readPNG(const std::string& path);
void writePNG(const std::string& path, const RGBImage& image);

/// The RGB of an 8-bit vtkImageData (the output of vtkWindowToImageFilter or a reader).
RGBImage fromImageData(vtkImageData* image);
/// The back buffer of the window (what vtkWindowToImageFilter reads after a Render).
RGBImage fromWindow(vtkRenderWindow* window);

/// The thresholds of a baseline: the line of its file stem in thresholds.txt beside it.
/// Throws std::runtime_error when the table or the line is missing.
ImageThresholds thresholdsOf(const std::string& baselinePath);

/// The file name of a path without its folder and extension.
std::string stemOf(const std::string& path);

/// The check of an image test: writes the test image to testDirectory/<stem of the
/// baseline>.png (where the perturbation check reads it), compares it with the baseline
/// under the baseline's thresholds and prints the result. True when it passes; false with
/// a message when the baseline or its thresholds are missing.
bool checkAgainstBaseline(const RGBImage& image,
  const std::string& baselinePath,
  const std::string& testDirectory);

}

#endif
