#include "BenchRun.h"

#include "vtkCamera.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkWindowToImageFilter.h"
#include "vtksys/SystemTools.hxx"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace bench
{

double ResidentMb()
{
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double Median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

double Now()
{
  return std::chrono::duration<double, std::milli>(
    std::chrono::steady_clock::now().time_since_epoch())
    .count();
}

Result Measure(const Options& opt,
  const Method& m,
  const std::function<void(vtkCamera*)>& view,
  const std::function<void(vtkRenderer*)>& inspect)
{
  const int repeat = m.repeat > 0 ? m.repeat : opt.repeat;
  vtkNew<vtkRenderer> ren;
  ren->SetBackground(1, 1, 1);
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  // No multisampling, as in ParaView's render views: VTK's default of 8 samples costs every
  // frame a resolve of the whole window (28 ms at 1024x1024 on Mesa here, an empty scene)
  // that no method here needs and a ParaView user does not pay.
  win->SetMultiSamples(0);
  win->SetSize(opt.width, opt.height);
  win->AddRenderer(ren);
  m.setup(ren);
  view(ren->GetActiveCamera());
  ren->ResetCameraClippingRange();

  const double mem0 = ResidentMb();
  double t0 = Now();
  win->Render();
  win->WaitForCompletion();
  const double first = Now() - t0;
  const double mem1 = ResidentMb();
  double build = m.buildMs ? m.buildMs() : -1.0;
  std::vector<double> times;
  for (int i = 0; i < repeat; ++i)
  {
    t0 = Now();
    win->Render();
    win->WaitForCompletion();
    times.push_back(Now() - t0);
  }
  // The build of a time step: the data marked modified and rendered again, --repeat times.
  if (m.buildMs && m.touch)
  {
    std::vector<double> builds;
    for (int i = 0; i < repeat; ++i)
    {
      m.touch();
      win->Render();
      win->WaitForCompletion();
      builds.push_back(m.buildMs());
    }
    build = Median(builds);
  }
  if (m.buildDetail)
  {
    std::cout << "  " << m.name << " " << m.setting << ": " << m.buildDetail() << std::endl;
  }
  Result r;
  r.row.method = m.name;
  r.row.setting = m.setting;
  r.row.width = opt.width;
  r.row.height = opt.height;
  r.row.renderMs = Median(times);
  r.row.buildMs = build >= 0 ? build : std::max(0.0, first - r.row.renderMs);
  r.row.memMb = std::max(0.0, mem1 - mem0);
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(win);
  grab->ReadFrontBufferOff();
  grab->SetInputBufferTypeToRGB();
  grab->Update();
  r.image = vtkSmartPointer<vtkImageData>::New();
  r.image->DeepCopy(grab->GetOutput());
  if (inspect)
  {
    inspect(ren);
  }
  return r;
}

void Compare(vtkImageData* a, vtkImageData* b, double& rmse, double& maxErr)
{
  auto* pa = static_cast<unsigned char*>(a->GetScalarPointer());
  auto* pb = static_cast<unsigned char*>(b->GetScalarPointer());
  const long n = static_cast<long>(a->GetNumberOfPoints()) * 3;
  double sum = 0, mx = 0;
  for (long i = 0; i < n; ++i)
  {
    const double d = (static_cast<int>(pa[i]) - static_cast<int>(pb[i])) / 255.0;
    sum += d * d;
    mx = std::max(mx, std::fabs(d));
  }
  rmse = std::sqrt(sum / static_cast<double>(n));
  maxErr = mx;
}

void WritePng(vtkImageData* image, const std::string& path)
{
  vtkNew<vtkPNGWriter> w;
  w->SetInputData(image);
  w->SetFileName(path.c_str());
  w->Write();
}

bool Selected(const Options& opt, const Method& m)
{
  // The leading ':' lets "--only :rbf:" pick the method rbf and not direct-rbf; a trailing
  // '$' anchors at the setting's end (":zsweep:exact$" and not ":zsweep:exact;sparse").
  const std::string key = ":" + m.name + ":" + m.setting;
  return opt.only.empty() ||
         std::any_of(opt.only.begin(),
           opt.only.end(),
           [&](const std::string& o)
           {
             if (!o.empty() && o.back() == '$')
             {
               const std::string tail = o.substr(0, o.size() - 1);
               return key.size() >= tail.size() &&
                 key.find(tail, key.size() - tail.size()) != std::string::npos;
             }
             return key.find(o) != std::string::npos;
           });
}

bool ViewSelected(const Options& opt, const std::string& view)
{
  return opt.views.empty() || std::find(opt.views.begin(), opt.views.end(), view) != opt.views.end();
}

std::string Generated(const Options& opt, const std::string& name, const std::string& script)
{
  const std::string path = opt.generated + "/" + name;
  if (!vtksys::SystemTools::FileExists(path, true))
  {
    vtksys::SystemTools::MakeDirectory(opt.generated);
    const std::string cmd = std::string("bash '") + RAYMAPPERS_SOURCE_DIR + "/Data/Generators/" +
                            script + "' '" + path + "'";
    std::cout << "generating " << name << " (a few minutes, once): " << cmd << std::endl;
    if (std::system(cmd.c_str()) != 0)
    {
      std::cerr << "raymappers-bench: " << name << " could not be generated; skipping it\n";
      return "";
    }
  }
  return path;
}

void WarmUp(const Options& opt)
{
  vtkNew<vtkRenderer> ren;
  vtkNew<vtkRenderWindow> win;
  win->SetOffScreenRendering(1);
  win->SetMultiSamples(0);
  win->SetSize(opt.width, opt.height);
  win->AddRenderer(ren);
  win->Render();
  win->WaitForCompletion();
}

const char* const CsvHeader =
  "suite,dataset,method,setting,width,height,items,build_ms,render_ms,rmse,max_err,mem_mb";

void Record(const Options& opt, const Result& result, std::vector<Row>& rows)
{
  const Row& row = result.row;
  rows.push_back(row);
  if (!opt.images.empty())
  {
    std::string tag = row.method + "-" + row.setting;
    for (char& c : tag)
    {
      c = c == ';' || c == '/' ? '_' : (c == '=' ? '-' : c);
    }
    WritePng(result.image, opt.images + "/" + row.suite + "-" + row.dataset + "-" + tag + ".png");
  }
  if (!opt.csv.empty())
  {
    std::ofstream out(opt.csv, std::ios::app);
    out << Csv(row) << std::endl;
  }
}

std::string Csv(const Row& r)
{
  std::ostringstream s;
  s << r.suite << "," << r.dataset << "," << r.method << "," << r.setting << "," << r.width << ","
    << r.height << "," << r.items << "," << r.buildMs << "," << r.renderMs << ",";
  if (r.rmse >= 0)
  {
    s << r.rmse;
  }
  s << ",";
  if (r.maxErr >= 0)
  {
    s << r.maxErr;
  }
  s << "," << r.memMb;
  return s.str();
}

void PrintTable(const std::vector<Row>& rows)
{
  std::printf("\n%-10s %-22s %-20s %-20s %10s %10s %10s %8s %8s %8s\n",
    "suite",
    "dataset",
    "method",
    "setting",
    "items",
    "build_ms",
    "render_ms",
    "rmse",
    "max_err",
    "mem_mb");
  for (const Row& r : rows)
  {
    char rmse[32] = "", maxErr[32] = "";
    if (r.rmse >= 0)
    {
      std::snprintf(rmse, sizeof rmse, "%.4f", r.rmse);
      std::snprintf(maxErr, sizeof maxErr, "%.3f", r.maxErr);
    }
    std::printf("%-10s %-22s %-20s %-20s %10lld %10.1f %10.1f %8s %8s %8.1f\n",
      r.suite.c_str(),
      r.dataset.c_str(),
      r.method.c_str(),
      r.setting.c_str(),
      r.items,
      r.buildMs,
      r.renderMs,
      rmse,
      maxErr,
      r.memMb);
  }
}

} // namespace bench
