#include "oovr/experiments/hardware.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/parallel.h"
#include "oovr/core/text.h"
#include "oovr/experiments/frames.h"
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

HardwareData HardwareData::parse(const std::string& text, const std::string& name) {
  HardwareData d;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  std::map<std::string, size_t> col;
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
      if (f[0] == "renderer") {
        if (f.size() < 2 || f[1].empty()) throw fail("the renderer line names no renderer");
        d.renderer = line.substr(line.find(',') + 1);
        continue;
      }
      for (size_t i = 0; i < f.size(); ++i) col[f[i]] = i;
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
  std::map<std::string, std::shared_ptr<const Scene>> scenes;
  for (const auto& f : data.frames)
    if (!scenes.count(f.scene)) {
      auto s = std::make_shared<const Scene>(load_scene(f.scene));
      if (s->objects.size() != f.draws)
        c.notes.push_back(f.scene + ": the data were measured with " + std::to_string(f.draws) + " draws, oovr's scene has " +
                          std::to_string(s->objects.size()));
      scenes.emplace(f.scene, std::move(s));
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
      w.aniso = o.aniso;
      w.use_cache = o.use_cache;
      const FrameWindow f = load_window(scene, rig, o.config, w);
      p.oovr_us[i] = run_scheme_window(o.scheme, *f.scene, *f.frames, o.config, 1).frame_latency_s * 1e6;
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
    gpu.push_back(p.gpu_median_us);
    sim.push_back(p.oovr_median_us);
    lo = lo == 0 ? p.ratio() : std::min(lo, p.ratio());
    hi = std::max(hi, p.ratio());
    auto& w = within[p.scene];
    w.first.insert(w.first.end(), p.gpu_us.begin(), p.gpu_us.end());
    w.second.insert(w.second.end(), p.oovr_us.begin(), p.oovr_us.end());
  }
  c.r = pearson(gpu, sim);
  c.spread = lo > 0 ? hi / lo : 0;
  double mean = 0, var = 0;
  for (const auto& p : c.points) mean += std::log(p.ratio()) / double(c.points.size());
  for (const auto& p : c.points) var += (std::log(p.ratio()) - mean) * (std::log(p.ratio()) - mean) / double(c.points.size());
  c.log_sd = std::sqrt(var);
  for (const auto& [scene, w] : within) c.r_within[scene] = pearson(w.first, w.second);
  return c;
}

}  // namespace oovr
