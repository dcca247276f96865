#include "ImageFiles.h"

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGReader.h"
#include "vtkPNGWriter.h"
#include "vtkRenderWindow.h"
#include "vtkWindowToImageFilter.h"

#include <cstdio>
#include <stdexcept>

namespace raymappers::test
{

RGBImage fromImageData(vtkImageData* image)
{
  RGBImage out;
  if (!image || image->GetScalarType() != VTK_UNSIGNED_CHAR ||
      image->GetNumberOfScalarComponents() < 3)
  {
    throw std::runtime_error("not an 8-bit RGB image");
  }
  int dims[3];
  image->GetDimensions(dims);
  out.width = dims[0];
  out.height = dims[1];
  const int n = image->GetNumberOfScalarComponents();
  const auto* p = static_cast<const unsigned char*>(image->GetScalarPointer());
  out.rgb.resize(3 * static_cast<std::size_t>(out.width) * out.height);
  for (std::size_t i = 0; i < static_cast<std::size_t>(out.width) * out.height; ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      out.rgb[3 * i + c] = p[n * i + c];
    }
  }
  return out;
}

RGBImage readPNG(const std::string& path)
{
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(path.c_str()))
  {
    throw std::runtime_error("cannot read the PNG file " + path);
  }
  reader->SetFileName(path.c_str());
  reader->Update();
  return fromImageData(reader->GetOutput());
}

void writePNG(const std::string& path, const RGBImage& image)
{
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  std::copy(
    image.rgb.begin(), image.rgb.end(), static_cast<unsigned char*>(data->GetScalarPointer()));
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(data);
  writer->SetFileName(path.c_str());
  writer->Write();
}

RGBImage fromWindow(vtkRenderWindow* window)
{
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  return fromImageData(grab->GetOutput());
}

std::string stemOf(const std::string& path)
{
  const std::size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.find_last_of('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

ImageThresholds thresholdsOf(const std::string& baselinePath)
{
  const std::size_t slash = baselinePath.find_last_of('/');
  const std::string folder = slash == std::string::npos ? "." : baselinePath.substr(0, slash);
  const auto table = readThresholdTable(folder + "/thresholds.txt");
  const auto it = table.find(stemOf(baselinePath));
  if (it == table.end())
  {
    throw std::runtime_error(
      "no thresholds for " + stemOf(baselinePath) + " in " + folder + "/thresholds.txt");
  }
  return it->second;
}

bool checkAgainstBaseline(const RGBImage& image,
  const std::string& baselinePath,
  const std::string& testDirectory)
{
  const std::string output = testDirectory + "/" + stemOf(baselinePath) + ".png";
  writePNG(output, image);
  try
  {
    const ImageThresholds t = thresholdsOf(baselinePath);
    const ImageDifference d = compareImages(image, readPNG(baselinePath), t.tolerance);
    std::printf(
      "%s against %s: %s\n", output.c_str(), baselinePath.c_str(), describe(d, t).c_str());
    return withinThresholds(d, t);
  }
  catch (const std::exception& e)
  {
    std::printf("image check of %s failed: %s\n", output.c_str(), e.what());
    return false;
  }
}

}
