// SPDX-License-Identifier: BSD-3-Clause
// sightline-benchmark: runs named scenes with every rendering method they register, measures
// build and frame times and the image error against the scene's reference method, and writes
// <output>/<scene>.csv, PNG images of every method and (through plot_benchmarks.py) a plot.
#include "BenchmarkSupport.h"
#include "SceneRegistry.h"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <stdexcept>

namespace fs = std::filesystem;
using namespace sightline_benchmark;

namespace
{
void printUsage(std::ostream& out)
{
  out
    << "Usage: sightline-benchmark --scene NAME [options]\n"
       "       sightline-benchmark --list\n"
       "\n"
       "Options:\n"
       "  --scene NAME            scene to run (see --list)\n"
       "  --spheres N[,N...]      primitive counts (alias --count; k and M suffixes allowed,\n"
       "                          e.g. 100k,1M); default: the scene's counts\n"
       "  --width W, --height H   image size (default 1920 x 1080)\n"
       "  --runs R                timed frames per method; the median is reported (default 5)\n"
       "  --output DIR            where <scene>.csv, <scene>.png and images/ go\n"
       "                          (default sightline-benchmark-results)\n"
       "  --tessellation R[,R...] vtkSphereSource resolutions of the tessellated baselines\n"
       "                          (default 8,16,32; 'none' for no baseline)\n"
       "  --max-triangles T       skip tessellations with more triangles (default 100M)\n"
       "  --seed S                random seed of the scene (default 20240601)\n"
       "  --data-dir DIR          where scenes that read real data find it or generate it\n"
       "                          (default: a folder in --output)\n"
       "  --methods S[,S...]      sh-glyphs, tensor-glyphs, tubes: only the methods whose name contains one of\n"
       "                          these (the reference and the exact or default method always run)\n"
       "  --no-plot               do not run plot_benchmarks.py at the end\n"
       "  --python PATH           Python with matplotlib (default " SIGHTLINE_BENCHMARK_PYTHON ")\n"
       "  --plot-script PATH      plot_benchmarks.py to run (default: installed next to this "
       "program)\n"
       "\n"
       "The OpenGL methods need a display: run under xvfb-run -a -s \"-noreset -screen 0 1920x1080x24\".\n";
}

long long parseCount(const std::string& text)
{
  std::size_t used = 0;
  double value = std::stod(text, &used);
  const std::string suffix = text.substr(used);
  if (suffix == "k" || suffix == "K")
  {
    value *= 1e3;
  }
  else if (suffix == "m" || suffix == "M")
  {
    value *= 1e6;
  }
  else if (!suffix.empty())
  {
    throw std::invalid_argument("bad count '" + text + "'");
  }
  if (!(value >= 1.0))
  {
    throw std::invalid_argument("counts must be positive, got '" + text + "'");
  }
  return std::llround(value);
}

std::vector<std::string> splitList(const std::string& text)
{
  std::vector<std::string> items;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ','))
  {
    if (!item.empty())
    {
      items.push_back(item);
    }
  }
  return items;
}

int parsePositive(const std::string& text, const char* what)
{
  const long long value = parseCount(text);
  if (value > 1000000000LL)
  {
    throw std::invalid_argument(std::string(what) + " is too large: " + text);
  }
  return static_cast<int>(value);
}

/// The plot script, installed (and copied into the build tree) at a fixed place relative to
/// this executable.
std::string defaultPlotScript()
{
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  if (error)
  {
    return {};
  }
  return (executable.parent_path() / SIGHTLINE_BENCHMARK_SCRIPTS_FROM_BINDIR / "plot_benchmarks.py")
    .lexically_normal()
    .string();
}

/// Numbers as CSV fields: empty when not measured.
std::string field(double value)
{
  if (!std::isfinite(value))
  {
    return {};
  }
  std::ostringstream s;
  s << std::setprecision(6) << value;
  return s.str();
}

std::string field(const std::string& text)
{
  if (text.find_first_of(",\"\n") == std::string::npos)
  {
    return text;
  }
  std::string quoted = "\"";
  for (char c : text)
  {
    quoted += c;
    if (c == '"')
    {
      quoted += '"';
    }
  }
  return quoted + "\"";
}

const MethodResult* findMethod(
  const std::vector<MethodResult>& rows, long long count, const std::string& method)
{
  for (const MethodResult& row : rows)
  {
    if (row.primitives == count && row.method == method && !row.skipped)
    {
      return &row;
    }
  }
  return nullptr;
}

/// Frame time relative to the "sightline" method of the same count (how many times slower).
double ratioToSightline(const std::vector<MethodResult>& rows, const MethodResult& row)
{
  const MethodResult* sightline = findMethod(rows, row.primitives, "sightline");
  if (!sightline || row.skipped)
  {
    return kNotMeasured;
  }
  return row.frame.medianSeconds / sightline->frame.medianSeconds;
}

void writeCsv(const std::string& path, const std::string& scene,
  const std::vector<MethodResult>& rows, const MachineDescription& machine)
{
  std::ofstream out(path);
  out << "scene,method,status,primitives,triangles,width,height,build_seconds,"
         "first_image_seconds,frame_seconds_median,frame_seconds_min,runs,"
         "frame_time_vs_sightline,bytes_per_primitive,rgb_mean_abs_diff,coverage_diff_percent,"
         "depth_max_abs_diff,depth_p99_abs_diff,hit_percent,interactive_frame_seconds_median,"
         "interactive_frame_seconds_min,memory_bytes,rss_increase_bytes,update_seconds,"
         "integral_rms_error,integral_max_error,notes,"
         "cpu_model,logical_cores,tbb_threads,memory_gib,load_average,gl_renderer,gl_version,vtk_version,embree_version,"
         "date\n";
  for (const MethodResult& row : rows)
  {
    const std::string status = row.skipped ? "skipped" : row.isReference ? "reference" : "ok";
    out << field(scene) << ',' << field(row.method) << ',' << status << ',' << row.primitives << ','
        << row.triangles << ',' << row.width << ',' << row.height << ',' << field(row.buildSeconds)
        << ',' << field(row.firstImageSeconds) << ',' << field(row.frame.medianSeconds) << ','
        << field(row.frame.minSeconds) << ',' << row.frame.runs << ','
        << field(ratioToSightline(rows, row)) << ',' << field(row.bytesPerPrimitive) << ','
        << field(row.error.rgbMeanAbsDiff) << ',' << field(row.error.coverageDiffPercent) << ','
        << field(row.error.depthMaxAbsDiff) << ',' << field(row.error.depthP99AbsDiff) << ','
        << field(row.hitPercent) << ',' << field(row.interactiveFrame.medianSeconds) << ','
        << field(row.interactiveFrame.minSeconds) << ',' << field(row.memoryBytes) << ','
        << field(row.rssIncreaseBytes) << ',' << field(row.updateSeconds) << ','
        << field(row.integralRmsError) << ',' << field(row.integralMaxError) << ',' << field(row.notes)
        << ',' << field(machine.cpuModel) << ','
        << machine.logicalCores << ',' << machine.tbbThreads << ',' << field(machine.memoryGiB)
        << ',' << field(machine.loadAverage) << ',' << field(machine.glRenderer) << ','
        << field(machine.glVersion) << ',' << field(machine.vtkVersion) << ','
        << field(machine.embreeVersion) << ',' << field(machine.date) << '\n';
  }
  if (!out)
  {
    throw std::runtime_error("could not write " + path);
  }
}

std::string cell(double value, int precision, bool scientific = false)
{
  if (!std::isfinite(value))
  {
    return "-";
  }
  std::ostringstream s;
  if (scientific)
  {
    s << std::scientific;
  }
  else
  {
    s << std::fixed;
  }
  s << std::setprecision(precision) << value;
  return s.str();
}

void printMachine(std::ostream& out, const MachineDescription& machine)
{
  out << "Machine: " << machine.cpuModel << "; " << machine.logicalCores << " logical cores, "
      << machine.tbbThreads << " TBB threads, " << cell(machine.memoryGiB, 1) << " GiB; load "
      << cell(machine.loadAverage, 2) << " at the start\n"
      << "OpenGL:  " << machine.glRenderer << " (" << machine.glVersion << ")\n"
      << "VTK " << machine.vtkVersion << ", Embree " << machine.embreeVersion << ", "
      << machine.date << "\n";
}

void printTable(std::ostream& out, const std::string& scene, const std::vector<MethodResult>& rows)
{
  const char* const header[] = { "count", "method", "build s", "1st img s", "frame med s",
    "frame min s", "x sightline", "B/prim", "RGB err", "cover %", "depth max", "depth p99",
    "hit %" };
  const int widths[] = { 9, 20, 9, 10, 12, 12, 12, 9, 8, 8, 10, 10, 6 };
  out << "\nScene '" << scene << "'\n";
  for (int i = 0; i < 13; ++i)
  {
    out << (i == 1 ? std::left : std::right) << std::setw(widths[i]) << header[i] << ' ';
  }
  out << '\n';
  for (const MethodResult& row : rows)
  {
    out << std::right << std::setw(widths[0]) << row.primitives << ' ' << std::left
        << std::setw(widths[1]) << row.method << ' ' << std::right;
    if (row.skipped)
    {
      out << row.notes << '\n';
      continue;
    }
    const std::string cells[] = { cell(row.buildSeconds, 3), cell(row.firstImageSeconds, 3),
      cell(row.frame.medianSeconds, 4), cell(row.frame.minSeconds, 4),
      cell(ratioToSightline(rows, row), 2), cell(row.bytesPerPrimitive, 1),
      cell(row.error.rgbMeanAbsDiff, 3), cell(row.error.coverageDiffPercent, 3),
      cell(row.error.depthMaxAbsDiff, 1, true), cell(row.error.depthP99AbsDiff, 1, true),
      cell(row.hitPercent, 1) };
    for (int i = 0; i < 11; ++i)
    {
      out << std::setw(widths[i + 2]) << cells[i] << ' ';
    }
    out << '\n';
  }
  out << "Errors are against the reference method (status 'reference' in the CSV); depth is "
         "window depth in [0, 1].\n";
}

std::string shellQuote(const std::string& text)
{
  std::string quoted = "'";
  for (char c : text)
  {
    quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  }
  return quoted + "'";
}

void runPlot(const Options& options, const std::string& csvPath)
{
  const std::string command =
    shellQuote(options.python) + " " + shellQuote(options.plotScript) + " " + shellQuote(csvPath);
  if (options.plotScript.empty() || access(options.plotScript.c_str(), R_OK) != 0 ||
    access(options.python.c_str(), X_OK) != 0)
  {
    std::cout << "Plot not made (no " << options.python << " or plot script); run:\n  " << command
              << "\n";
    return;
  }
  logProgress("plotting: " + command);
  std::cout.flush(); // keep the table before the script's output
  if (std::system(command.c_str()) != 0)
  {
    std::cout << "The plot script failed; the CSV is complete. Command:\n  " << command << "\n";
  }
}

Options parseArguments(int argc, char* argv[], bool& list, bool& help)
{
  Options options;
  options.python = SIGHTLINE_BENCHMARK_PYTHON;
  options.plotScript = defaultPlotScript();
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string
    {
      if (i + 1 >= argc)
      {
        throw std::invalid_argument(arg + " needs a value");
      }
      return argv[++i];
    };
    if (arg == "--list")
      list = true;
    else if (arg == "--help" || arg == "-h")
      help = true;
    else if (arg == "--scene")
      options.scene = value();
    else if (arg == "--spheres" || arg == "--count")
    {
      options.counts.clear();
      for (const std::string& item : splitList(value()))
        options.counts.push_back(parseCount(item));
    }
    else if (arg == "--width")
      options.width = parsePositive(value(), "--width");
    else if (arg == "--height")
      options.height = parsePositive(value(), "--height");
    else if (arg == "--runs")
      options.runs = parsePositive(value(), "--runs");
    else if (arg == "--output")
      options.outputDirectory = value();
    else if (arg == "--tessellation")
    {
      options.tessellations.clear();
      const std::string list = value();
      if (list != "none")
      {
        for (const std::string& item : splitList(list))
        {
          const int resolution = parsePositive(item, "--tessellation");
          if (resolution < 3)
            throw std::invalid_argument("tessellation resolutions must be at least 3");
          options.tessellations.push_back(resolution);
        }
      }
    }
    else if (arg == "--max-triangles")
      options.maxTriangles = parseCount(value());
    else if (arg == "--seed")
      options.seed = static_cast<unsigned>(std::stoul(value()));
    else if (arg == "--data-dir")
      options.dataDirectory = value();
    else if (arg == "--methods")
    {
      std::stringstream list(value());
      for (std::string name; std::getline(list, name, ',');)
        if (!name.empty())
          options.methodFilter.push_back(name);
    }
    else if (arg == "--no-plot")
      options.plot = false;
    else if (arg == "--python")
      options.python = value();
    else if (arg == "--plot-script")
      options.plotScript = value();
    else
      throw std::invalid_argument("unknown argument '" + arg + "'");
  }
  return options;
}
} // namespace

int main(int argc, char* argv[])
{
  bool list = false, help = false;
  Options options;
  try
  {
    options = parseArguments(argc, argv, list, help);
  }
  catch (const std::exception& e)
  {
    std::cerr << "sightline-benchmark: " << e.what() << "\n\n";
    printUsage(std::cerr);
    return 2;
  }
  if (help)
  {
    printUsage(std::cout);
    return 0;
  }
  if (list)
  {
    for (const Scene* scene : SceneRegistry::instance().scenes())
    {
      std::cout << scene->name << ": " << scene->description << "\n";
    }
    return 0;
  }
  const Scene* scene = SceneRegistry::instance().find(options.scene);
  if (!scene)
  {
    std::cerr << "sightline-benchmark: "
              << (options.scene.empty() ? "no --scene given" : "no scene '" + options.scene + "'")
              << "; --list shows the scenes.\n";
    return 2;
  }
  if (options.counts.empty())
  {
    options.counts = scene->defaultCounts;
  }
  logProgress("sightline-benchmark --scene " + scene->name);

  try
  {
    const fs::path output(options.outputDirectory);
    const fs::path images = output / "images";
    fs::create_directories(images);
    MachineDescription machine = MachineDescription::probe();
    if (machine.loadAverage > 0.25 * machine.logicalCores)
    {
      logProgress("warning: load average " + std::to_string(machine.loadAverage) + " on " +
        std::to_string(machine.logicalCores) +
        " cores: other processes are busy and the timings will be noisy");
    }

    std::vector<MethodResult> rows;
    for (long long count : options.counts)
    {
      std::vector<MethodResult> results = scene->run(options, count, machine);
      const MethodResult* reference = nullptr;
      for (const MethodResult& result : results)
      {
        if (result.isReference && !result.skipped)
          reference = &result;
      }
      for (MethodResult& result : results)
      {
        if (result.skipped)
          continue;
        if (reference)
          result.error = compareImages(result.image, reference->image);
        result.hitPercent = hitPercent(result.image);
        const std::string stem = scene->name + "-" + std::to_string(count) + "-" + result.method;
        writeImagePNGs(result.image, (images / (stem + ".png")).string(),
          (images / (stem + "-crop.png")).string());
        if (reference && !result.isReference)
          writeDifferencePNG(
            result.image, reference->image, (images / (stem + "-diff.png")).string());
      }
      for (MethodResult& result : results)
      {
        result.image = Image(); // written; keep memory for the next count
        rows.push_back(std::move(result));
      }
    }

    const std::string csvPath = (output / (scene->name + ".csv")).string();
    writeCsv(csvPath, scene->name, rows, machine);
    std::cout << "\n";
    printMachine(std::cout, machine);
    printTable(std::cout, scene->name, rows);
    std::cout << "\nCSV:    " << csvPath << "\nImages: " << images.string() << "/" << scene->name
              << "-<count>-<method>[-crop|-diff].png\n";
    if (options.plot)
    {
      runPlot(options, csvPath);
    }
  }
  catch (const std::exception& e)
  {
    std::cerr << "sightline-benchmark: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
