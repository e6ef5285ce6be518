#include "io/deviation.hpp"

#ifdef VARSPH_HAVE_VTK

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>
#include <unordered_map>

#include "core/errors.hpp"
#include "core/particle_store.hpp"
#include "io/atomic_file.hpp"
#include "io/frame_data.hpp"
#include "io/pvd_series.hpp"

namespace varsph::io {
namespace fs = std::filesystem;
namespace {

struct SeriesEntry {
  double time;
  fs::path file;
};

fs::path find_pvd(const fs::path& run) {
  if (fs::is_regular_file(run) && run.extension() == ".pvd") return run;
  if (!fs::is_directory(run)) throw InputError(run.string() + ": not a run directory or .pvd file");
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(run))
    if (e.path().extension() == ".pvd" && e.path().filename() != "deviation.pvd") found.push_back(e.path());
  if (found.size() != 1)
    throw InputError(run.string() + ": expected exactly one .pvd time series in the run directory, found " +
                     std::to_string(found.size()));
  return found.front();
}

std::vector<SeriesEntry> read_series(const fs::path& pvd) {
  std::ifstream in(pvd);
  if (!in) throw InputError(pvd.string() + ": cannot be read");
  std::vector<SeriesEntry> out;
  const std::regex re(R"re(<DataSet[^>]*timestep="([^"]+)"[^>]*file="([^"]+)")re");
  std::string line;
  while (std::getline(in, line)) {
    std::smatch m;
    // part 1 is a run's static walls (output.static_boundary = "once"): no fluid to compare
    if (line.find("part=\"1\"") != std::string::npos) continue;
    if (std::regex_search(line, m, re)) out.push_back({std::stod(m[1].str()), pvd.parent_path() / m[2].str()});
  }
  if (out.empty()) throw InputError(pvd.string() + ": no frames (DataSet entries) in the time series");
  return out;
}

struct Frame {
  double time = 0;
  std::unordered_map<std::int64_t, std::array<double, 3>> fluid;  // id -> position
  std::vector<std::int64_t> order;                                // ids in file order
};

Frame read_frame(const fs::path& file, double pvd_time) {
  if (!fs::exists(file)) throw InputError(file.string() + ": frame listed in the .pvd does not exist");
  // a serial frame (.vtu) or a distributed one (.pvtu and its pieces, docs/parallel.md)
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  vtkNew<vtkXMLPUnstructuredGridReader> preader;
  vtkUnstructuredGrid* g = nullptr;
  if (file.extension() == ".pvtu") {
    preader->SetFileName(file.c_str());
    preader->Update();
    g = preader->GetOutput();
  } else {
    reader->SetFileName(file.c_str());
    reader->Update();
    g = reader->GetOutput();
  }
  if (!g || !g->GetPoints()) throw InputError(file.string() + ": not a readable VTU frame");
  vtkDataArray* id = g->GetPointData()->GetArray("id");
  vtkDataArray* kind = g->GetPointData()->GetArray("kind");
  if (!id) throw InputError(file.string() + ": point array 'id' missing (needed to match particles)");
  Frame f;
  f.time = pvd_time;
  if (vtkDataArray* t = g->GetFieldData()->GetArray("time"); t && t->GetNumberOfTuples() > 0)
    f.time = t->GetTuple1(0);  // full precision (the .pvd has 6 digits)
  const vtkIdType n = g->GetNumberOfPoints();
  for (vtkIdType i = 0; i < n; ++i) {
    if (kind && kind->GetTuple1(i) != 0) continue;  // fluid particles only
    const auto key = std::int64_t(id->GetTuple1(i));
    double p[3];
    g->GetPoint(i, p);
    f.fluid[key] = {p[0], p[1], p[2]};
    f.order.push_back(key);
  }
  return f;
}

std::string num(double v) {
  std::ostringstream o;
  o.precision(17);
  o << v;
  return o.str();
}

}  // namespace

std::vector<DeviationRow> compare_runs(const CompareOptions& o) {
  const fs::path pa = find_pvd(o.run_a), pb = find_pvd(o.run_b);
  const auto sa = read_series(pa), sb = read_series(pb);
  // pair frames by time (the .pvd times first, refined by the frames' own field data below)
  std::vector<std::pair<SeriesEntry, SeriesEntry>> pairs;
  for (const auto& ea : sa)
    for (const auto& eb : sb)
      if (std::abs(ea.time - eb.time) <= std::max(o.time_tolerance, 1e-6 * std::abs(ea.time))) {
        pairs.push_back({ea, eb});
        break;
      }
  if (pairs.empty())
    throw InputError(pa.string() + " and " + pb.string() + ": the runs have no frame times in common");

  if (fs::exists(o.output) && !fs::is_empty(o.output)) {
    if (!o.overwrite) throw InputError(o.output.string() + ": output directory exists and is not empty (use --overwrite)");
    fs::remove_all(o.output);
  }
  try {
    fs::create_directories(o.output / "frames");
  } catch (const fs::filesystem_error& e) {
    throw IoError(o.output.string() + ": cannot create the output directory: " + e.what());
  }
  PvdSeries pvd(o.output / "deviation.pvd");
  std::vector<DeviationRow> rows;
  ParticleStore store;
  auto& pos = store.add<Vec<3>>("position");
  auto& dev = store.add<Vec<3>>("deviation");
  auto& mag = store.add<Real>("deviation_magnitude");
  auto& ids = store.add<std::int64_t>("id");
  std::ostringstream csv;
  csv << "time,D_max,D_mean,D_rms,matched,only_a,only_b\n";
  long index = 0;
  for (const auto& [ea, eb] : pairs) {
    const Frame fa = read_frame(ea.file, ea.time), fb = read_frame(eb.file, eb.time);
    if (std::abs(fa.time - fb.time) > o.time_tolerance) continue;  // .pvd rounding matched them, field data does not
    // particles are matched by id; one a run removed (health.*) is left out and counted
    DeviationRow r;
    r.time = fa.time;
    for (const auto id : fa.order) (fb.fluid.count(id) ? r.matched : r.only_a) += 1;
    r.only_b = long(fb.fluid.size()) - r.matched;
    // both runs start from the same particles: at the first common time the sets must agree; later a
    // particle may be missing from one run only because its health rules removed it
    if (rows.empty() && (r.only_a > 0 || r.only_b > 0))
      throw InputError(ea.file.string() + " and " + eb.file.string() + ": different fluid particle sets at the first "
                       "common time t = " + num(r.time) + " s (" + std::to_string(fa.fluid.size()) + " vs " +
                       std::to_string(fb.fluid.size()) + " particles, " + std::to_string(r.matched) + " ids in common)");
    store.resize(std::size_t(r.matched));
    double sum = 0, sum2 = 0;
    std::size_t k = 0;
    for (const auto id : fa.order) {
      const auto it = fb.fluid.find(id);
      if (it == fb.fluid.end()) continue;
      const auto& a = fa.fluid.at(id);
      const auto& b = it->second;
      Vec<3> d;
      for (int c = 0; c < 3; ++c) d[c] = Real(a[c] - b[c]);
      const double m = std::sqrt(double(d.squaredNorm()));
      pos[k] = Vec<3>(Real(a[0]), Real(a[1]), Real(a[2]));
      dev[k] = d;
      mag[k] = Real(m);
      ids[k] = id;
      r.d_max = std::max(r.d_max, m);  // seed eq. (70)
      sum += m;
      sum2 += m * m;
      ++k;
    }
    const double n = double(std::max<long>(r.matched, 1));
    r.d_mean = sum / n;
    r.d_rms = std::sqrt(sum2 / n);
    rows.push_back(r);
    csv << num(r.time) << ',' << num(r.d_max) << ',' << num(r.d_mean) << ',' << num(r.d_rms) << ',' << r.matched
        << ',' << r.only_a << ',' << r.only_b << '\n';

    FrameData frame;
    frame.dimension = 3;
    frame.positions = &pos;
    frame.float64 = true;
    frame.arrays = {{"deviation", &dev, true}, {"deviation_magnitude", &mag, false}, {"id", &ids, false}};
    frame.time = r.time;
    frame.step = index;
    frame.kernel = "n/a";
    char name[64];
    std::snprintf(name, sizeof name, "frames/deviation_%06ld.vtu", index);
    write_vtu((o.output / name).string(), frame);
    pvd.add(r.time, name);
    ++index;
  }
  if (rows.empty())
    throw InputError(pa.string() + " and " + pb.string() + ": no frame times agree within " +
                     num(o.time_tolerance) + " s");
  write_text_atomically(o.output / "deviation.csv", csv.str());
  return rows;
}

}  // namespace varsph::io

#else  // a build without VTK writes frames (io/vtu_writer.cpp) but cannot read them back

#include "core/errors.hpp"

namespace varsph::io {

std::vector<DeviationRow> compare_runs(const CompareOptions&) {
  throw InputError("varsph compare reads frames with VTK, which this build does not have (configured without "
                   "VTK: -DVARSPH_VTK=OFF or none found); compare the runs on a machine with VTK or ParaView");
}

}  // namespace varsph::io

#endif
