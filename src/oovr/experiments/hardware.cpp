#include "oovr/experiments/hardware.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/parallel.h"
#include "oovr/core/text.h"
#include "oovr/pipeline/tiled_layout.h"
#include "oovr/run/frames.h"
#include "oovr/scene/load.h"
#include "oovr/scene/stereo.h"
#include "oovr/schemes/i_scheme.h"

namespace oovr {

double median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double pearson(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = x.size();
  if (n != y.size() || n < 2) return 0;
  double mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= double(n);
  my /= double(n);
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  return sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0;
}

namespace {

// Text the data carries into messages and documents: printable ASCII only.
bool printable(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](char c) { return c >= 0x20 && c < 0x7f; });
}

// The workload lines before the header: key -> value.
void workload_line(HardwareData& d, const std::string& key, const std::string& value, std::map<std::string, int>& seen,
                   const std::function<Error(const std::string&)>& fail) {
  if (seen[key]++) throw fail("a second '" + key + "' line");
  if (value.empty() || value.size() > 200 || !printable(value)) throw fail("'" + key + "' needs a value of printable text");
  if (key == "renderer") {
    d.renderer = value;
  } else if (key == "commit") {
    // As `git describe --always --dirty` gives it, or "unknown".
    const std::string id = value.size() > 6 && value.ends_with("-dirty") ? value.substr(0, value.size() - 6) : value;
    const bool hex = id.size() >= 7 && id.size() <= 40 &&
                     std::all_of(id.begin(), id.end(), [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); });
    if (!hex && value != "unknown")
      throw fail("'commit' is oovr's commit (7 to 40 hex digits, -dirty after them) or unknown, not '" + value + "'");
    d.workload.commit = value;
  } else if (key == "materials") {
    if (value != "real" && value != "one-pass") throw fail("'materials' is real or one-pass, not '" + value + "'");
    d.workload.materials = value;
  } else if (key == "texture_format") {
    (void)parse_texture_format(value);  // names the formats when it is none of them
    d.workload.texture_format = value;
  } else if (key == "aniso") {
    const auto n = parse_whole_number(value, 1, 16);
    if (!n) throw fail("'aniso' is a whole number from 1 to 16, not '" + value + "'");
    d.workload.aniso = int(*n);
  }
}

}  // namespace

HardwareData HardwareData::parse(const std::string& text, const std::string& name) {
  HardwareData d;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  std::map<std::string, size_t> col;
  std::map<std::string, int> seen;
  const char* required[] = {"scene", "resolution", "frame", "full_us", "geom_us", "left_us", "draws", "triangles"};
  const auto fail = [&](const std::string& what) -> Error {
    return Error("hardware data '" + name + "' line " + std::to_string(number) + ": " + what);
  };
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> f = split_fields(line, ',');
    if (col.empty()) {
      if (f[0] == "renderer" || f[0] == "commit" || f[0] == "materials" || f[0] == "texture_format" || f[0] == "aniso") {
        // A renderer's name may hold commas; the other values may not.
        if (f[0] != "renderer" && f.size() != 2)
          throw fail("'" + f[0] + "' line has " + std::to_string(f.size()) + " fields, not 2");
        workload_line(d, f[0], f.size() < 2 ? "" : line.substr(line.find(',') + 1), seen, fail);
        continue;
      }
      for (const char* k : {"commit", "materials", "texture_format", "aniso"})
        if (!seen.count(k))
          throw fail(std::string("the data do not say what the GPU drew: no '") + k +
                     "' line before the header (docs/data/hardware/README.md)");
      for (size_t i = 0; i < f.size(); ++i)
        if (!col.emplace(f[i], i).second) throw fail("the header names the column '" + f[i] + "' twice");
      for (const char* r : required)
        if (!col.count(r)) throw fail(std::string("the header has no column '") + r + "'");
      continue;
    }
    if (f.size() != col.size())
      throw fail("has " + std::to_string(f.size()) + " fields, the header " + std::to_string(col.size()));
    HardwareFrame h;
    h.scene = f[col["scene"]];
    h.resolution = f[col["resolution"]];
    if (h.scene.empty()) throw fail("names no scene");
    if (h.scene.size() > 1000 || !printable(h.scene)) throw fail("a scene name of other than printable text");
    (void)parse_frame_resolution(h.resolution);
    const auto number_of = [&](const char* key, auto& out) {
      const std::string& s = f[col[key]];
      const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
      if (r.ec != std::errc() || r.ptr != s.data() + s.size())
        throw fail(std::string("'") + key + "' is not a number: '" + s + "'");
    };
    number_of("frame", h.frame);
    number_of("full_us", h.full_us);
    number_of("geom_us", h.geom_us);
    number_of("left_us", h.left_us);
    number_of("draws", h.draws);
    number_of("triangles", h.triangles);
    if (h.frame < 0) throw fail("a negative frame");
    if (!(h.full_us > 0 && h.full_us < 1e9)) throw fail("'full_us' is not a positive number of microseconds");
    for (double t : {h.geom_us, h.left_us})
      if (!(t >= 0 && t < 1e9)) throw fail("a time that is negative or not a number of microseconds");
    d.frames.push_back(std::move(h));
  }
  if (col.empty()) throw Error("hardware data '" + name + "' has no header line");
  if (d.frames.empty()) throw Error("hardware data '" + name + "' has no frames");
  return d;
}

HardwareData HardwareData::read(const std::string& path) {
  return parse(read_input_file(path, "hardware data", uint64_t(256) << 20), path);
}

std::string HardwareData::csv() const {
  std::ostringstream s;
  if (!renderer.empty()) s << "renderer," << renderer << "\n";
  s << "commit," << workload.commit << "\nmaterials," << workload.materials << "\ntexture_format," << workload.texture_format
    << "\naniso," << workload.aniso << "\n";
  s << "scene,resolution,frame,full_us,geom_us,left_us,draws,triangles\n";
  char buf[64];
  const auto us = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.3f", v);
    return std::string(buf);
  };
  for (const auto& f : frames)
    s << f.scene << ',' << f.resolution << ',' << f.frame << ',' << us(f.full_us) << ',' << us(f.geom_us) << ',' << us(f.left_us)
      << ',' << f.draws << ',' << f.triangles << "\n";
  return s.str();
}

Correlation correlate(const HardwareData& data, const CorrelationOptions& o) {
  if (scheme_frames_needed(o.scheme, o.config) != 1)
    throw Error("oovr correlate compares one frame at a time: scheme '" + o.scheme + "' renders several frames at once");
  Correlation c;
  c.scheme = o.scheme;
  c.workload = data.workload;
  // Textures stored as the GPU stored them, unless the configuration says
  // otherwise (then a note says so).
  Config config = o.config;
  if (!config.has("pipeline.texture_format")) {
    config.set_source("the hardware data");
    config.set("pipeline.texture_format", data.workload.texture_format);
  } else if (config.get_string("pipeline.texture_format", "") != data.workload.texture_format) {
    c.notes.push_back("pipeline.texture_format is " + config.get_string("pipeline.texture_format", "") +
                      "; the GPU stored its textures as " + data.workload.texture_format);
  }
  // The points, in the order the data lists them.
  std::map<std::pair<std::string, std::string>, size_t> index;
  for (const auto& f : data.frames) {
    const auto key = std::make_pair(f.scene, f.resolution);
    auto it = index.find(key);
    if (it == index.end()) {
      it = index.emplace(key, c.points.size()).first;
      c.points.push_back({f.scene, f.resolution, {}, {}, {}, 0, 0});
    }
    CorrelationPoint& p = c.points[it->second];
    if (std::find(p.frames.begin(), p.frames.end(), f.frame) != p.frames.end())
      throw Error("hardware data lists frame " + std::to_string(f.frame) + " of " + f.scene + " at " + f.resolution + " twice");
    p.frames.push_back(f.frame);
    p.gpu_us.push_back(f.full_us);
  }
  if (c.points.size() < 2) throw Error("hardware data needs at least two (scene, resolution) points to correlate");
  // Each scene must be the one the GPU drew: a loader or material change
  // since the data were measured changes the draws or the triangles.
  std::map<std::string, std::shared_ptr<const Scene>> scenes;
  std::map<std::string, uint64_t> triangles;
  for (const auto& f : data.frames) {
    if (!scenes.count(f.scene)) {
      auto s = std::make_shared<const Scene>(load_scene(f.scene));
      triangles[f.scene] = s->triangle_count();
      scenes.emplace(f.scene, std::move(s));
    }
    const size_t draws = scenes.at(f.scene)->objects.size();
    if (draws != f.draws || triangles.at(f.scene) != f.triangles)
      throw Error("scene '" + f.scene + "' is not the workload the GPU drew: the data were measured with " +
                  std::to_string(f.draws) + " draws and " + std::to_string(f.triangles) + " triangles (oovr " +
                  data.workload.commit + ", " + data.workload.materials + " materials), oovr's scene has " +
                  std::to_string(draws) + " draws and " + std::to_string(triangles.at(f.scene)) +
                  " triangles; measure it again (oovr-reference --time) or name the scene as it was drawn");
  }
  for (auto& p : c.points) {
    const std::shared_ptr<const Scene>& scene = scenes.at(p.scene);
    const StereoRig rig = parse_frame_resolution(p.resolution);
    p.oovr_us.assign(p.frames.size(), 0);
    // Frames are independent runs: in parallel, each into its own slot.
    std::vector<std::vector<std::string>> frame_notes(p.frames.size());
    parallel_for(p.frames.size(), 0, [&](size_t i) {
      WindowRequest w;
      w.first = p.frames[i];
      w.count = 1;
      w.aniso = data.workload.aniso;
      w.use_cache = o.use_cache;
      const FrameWindow f = load_window(scene, rig, config, w);
      p.oovr_us[i] = run_scheme_window(o.scheme, *f.scene, *f.frames, config, 1).frame_latency_s * 1e6;
      frame_notes[i] = f.notes;
    });
    for (const auto& n : frame_notes)
      for (const auto& x : n) c.notes.push_back(p.scene + " " + p.resolution + ": " + x);
    p.gpu_median_us = median(p.gpu_us);
    p.oovr_median_us = median(p.oovr_us);
    if (o.progress) o.progress(p.scene + " " + p.resolution + ": " + std::to_string(p.frames.size()) + " frames simulated");
  }
  std::vector<double> gpu, sim;
  std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> within;
  double lo = 0, hi = 0;
  for (const auto& p : c.points) {
    // A frame oovr simulates as taking no time is a defect, not a ratio.
    if (!(p.ratio() > 0 && std::isfinite(p.ratio())))
      throw Error("oovr's frame time for " + p.scene + " at " + p.resolution + " is " + std::to_string(p.oovr_median_us) +
                  " us: no ratio to the GPU's");
    gpu.push_back(p.gpu_median_us);
    sim.push_back(p.oovr_median_us);
    lo = gpu.size() == 1 ? p.ratio() : std::min(lo, p.ratio());
    hi = std::max(hi, p.ratio());
    auto& w = within[p.scene];
    w.first.insert(w.first.end(), p.gpu_us.begin(), p.gpu_us.end());
    w.second.insert(w.second.end(), p.oovr_us.begin(), p.oovr_us.end());
  }
  c.r = pearson(gpu, sim);
  c.spread = hi / lo;
  double mean = 0, var = 0;
  for (const auto& p : c.points) mean += std::log(p.ratio()) / double(c.points.size());
  for (const auto& p : c.points) var += (std::log(p.ratio()) - mean) * (std::log(p.ratio()) - mean) / double(c.points.size());
  c.log_sd = std::sqrt(var);
  for (const auto& [scene, w] : within) c.r_within[scene] = pearson(w.first, w.second);
  return c;
}

std::vector<LeftOut> leave_one_scene_out(const std::vector<std::string>& values, const std::vector<Correlation>& runs) {
  if (values.empty() || values.size() != runs.size()) throw Error("leave-one-scene-out: one correlation per value");
  std::vector<std::string> scenes;
  for (const auto& p : runs.front().points)
    if (std::find(scenes.begin(), scenes.end(), p.scene) == scenes.end()) scenes.push_back(p.scene);
  if (scenes.size() < 2) throw Error("leave-one-scene-out needs points of at least two scenes");
  // Mean and spread of log(oovr / GPU) over a selection of points.
  const auto logs = [](const Correlation& c, const std::function<bool(const CorrelationPoint&)>& take) {
    std::vector<double> v;
    for (const auto& p : c.points)
      if (take(p)) v.push_back(std::log(p.ratio()));
    return v;
  };
  const auto mean = [](const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m += x / double(v.size());
    return m;
  };
  std::vector<LeftOut> out;
  for (const auto& scene : scenes) {
    const auto others = [&](const CorrelationPoint& p) { return p.scene != scene; };
    size_t best = 0;
    double best_sd = 0;
    for (size_t i = 0; i < runs.size(); ++i) {
      const std::vector<double> v = logs(runs[i], others);
      const double m = mean(v);
      double var = 0;
      for (double x : v) var += (x - m) * (x - m) / double(v.size());
      if (i == 0 || std::sqrt(var) < best_sd) {
        best = i;
        best_sd = std::sqrt(var);
      }
    }
    const Correlation& c = runs[best];
    const double theirs = mean(logs(c, others));
    const double its = mean(logs(c, [&](const CorrelationPoint& p) { return p.scene == scene; }));
    out.push_back({scene, values[best], std::exp(its - theirs), c.r, c.spread});
  }
  return out;
}

}  // namespace oovr
