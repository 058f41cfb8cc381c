#include "oovr/scene/sources/torcs.h"

#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/scene/formats/ac3d.h"
#include "oovr/scene/load.h"
#include "oovr/scene/source.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

// TORCS values carry a unit attribute; without one they are SI (m, rad).
double to_si(const pugi::xml_node& attnum) {
  const double v = attnum.attribute("val").as_double(0.0);
  const std::string unit = attnum.attribute("unit").as_string("");
  if (unit == "deg") return v * 3.14159265358979323846 / 180.0;
  if (unit == "ft") return v * 0.3048;
  if (unit == "km") return v * 1000.0;
  if (unit == "cm") return v * 0.01;
  if (unit == "mm") return v * 0.001;
  return v;
}

pugi::xml_node child_section(const pugi::xml_node& n, const char* name) {
  return n.find_child_by_attribute("section", "name", name);
}

std::optional<double> attnum(const pugi::xml_node& section, const char* name) {
  const pugi::xml_node a = section.find_child_by_attribute("attnum", "name", name);
  if (!a) return std::nullopt;
  return to_si(a);
}

// Height of the model's surfaces under (x, z): all hits, from triangles
// whose projection on the ground plane contains the point.
std::vector<float> heights_at(const Scene& s, float x, float z) {
  std::vector<float> hits;
  for (const auto& o : s.objects) {
    const Mesh& m = s.meshes[size_t(o.mesh)];
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
      const Vec3 a = m.vertices[m.indices[t]].position, b = m.vertices[m.indices[t + 1]].position,
                 c = m.vertices[m.indices[t + 2]].position;
      if (x < std::min({a.x, b.x, c.x}) || x > std::max({a.x, b.x, c.x}) || z < std::min({a.z, b.z, c.z}) ||
          z > std::max({a.z, b.z, c.z}))
        continue;
      const float d = (b.x - a.x) * (c.z - a.z) - (c.x - a.x) * (b.z - a.z);
      if (std::abs(d) < 1e-9f) continue;
      const float u = ((x - a.x) * (c.z - a.z) - (c.x - a.x) * (z - a.z)) / d;
      const float v = ((b.x - a.x) * (z - a.z) - (x - a.x) * (b.z - a.z)) / d;
      if (u < 0 || v < 0 || u + v > 1) continue;
      hits.push_back(a.y + u * (b.y - a.y) + v * (c.y - a.y));
    }
  }
  return hits;
}

}  // namespace

std::string torcs_directory() {
  if (const char* d = std::getenv("OOVR_TORCS_DIR"); d && *d) return d;
  return "/usr/share/games/torcs";
}

std::vector<TorcsTrack> list_torcs_tracks() {
  std::vector<TorcsTrack> out;
  std::error_code ec;
  const fs::path root = fs::path(torcs_directory()) / "tracks";
  if (!fs::is_directory(root, ec)) return out;
  for (const auto& cat : fs::directory_iterator(root, ec)) {
    if (!cat.is_directory(ec)) continue;
    for (const auto& t : fs::directory_iterator(cat.path(), ec)) {
      const std::string name = t.path().filename().string();
      if (fs::is_regular_file(t.path() / (name + ".acc"), ec) || fs::is_regular_file(t.path() / (name + ".ac"), ec))
        out.push_back({name, cat.path().filename().string(), t.path().string()});
    }
  }
  std::sort(out.begin(), out.end(), [](const TorcsTrack& a, const TorcsTrack& b) { return a.name < b.name; });
  return out;
}

constexpr double kMaxTrackMetres = 1e6;  // 1,000 km: real tracks are under 10

std::vector<Vec3> torcs_centre_line(const std::string& xml_path) {
  return torcs_centre_line_from_text(read_input_file(xml_path, "track description", uint64_t(64) << 20), xml_path);
}

std::vector<Vec3> torcs_centre_line_from_text(const std::string& text, const std::string& xml_path) {
  pugi::xml_document doc;
  // No DTD processing: TORCS files name an external entity for surfaces,
  // which is not needed for the geometry.
  const pugi::xml_parse_result r = doc.load_buffer(text.data(), text.size(), pugi::parse_default & ~pugi::parse_doctype);
  if (!r) throw Error("cannot read track description '" + xml_path + "': " + r.description());
  const pugi::xml_node main = child_section(doc.child("params"), "Main Track");
  // Two generations of the format: TORCS's track4 reads "Track Segments"
  // with sides and borders in sections of their own ("Right Side": "start
  // width"); the older track3 (a-speedway, dirt-4 to 6, e-track-5, mixed-1
  // and 2) reads "segments" with them as attributes ("rside start width",
  // "rborder width"). The geometry is the same.
  pugi::xml_node segments = child_section(main, "Track Segments");
  const bool v3 = !segments;
  if (v3) segments = child_section(main, "segments");
  if (!segments) throw Error("track description '" + xml_path + "' has no Main Track / Track Segments (or segments) section");
  const auto bad = [&](const pugi::xml_node& seg, const std::string& what) {
    return Error("track description '" + xml_path + "': segment '" + seg.attribute("name").as_string() + "' " + what);
  };

  // The main track as TORCS builds it (track4.cpp, as its published
  // description of the format implies): the right edge starts at the origin
  // heading along +x, the left edge at (0, width); turns keep the centre
  // line at their radius; a spiral (radius to end radius) is cut into
  // profile steps of constant radius. Each side of the track has a border
  // and a side strip whose widths carry over from segment to segment. In the
  // end every coordinate is shifted so that the smallest x and y reached by
  // the track, its borders and sides (and the origin) become 0.
  // Every number must be finite and within 1e9 (metres, radians): a width
  // of 1e400 reads as infinity, and two widths of 1e308 add up to it; one
  // infinite coordinate makes the whole line so (found by fuzz_torcs).
  const auto number = [&](const pugi::xml_node& section, const char* name) {
    const std::optional<double> v = attnum(section, name);
    if (v && !(std::abs(*v) <= 1e9))
      throw Error("track description '" + xml_path + "': '" + name + "' is " +
                  section.find_child_by_attribute("attnum", "name", name).attribute("val").as_string() +
                  ", not a number within 1e9");
    return v;
  };
  const double width = number(main, "width").value_or(15.0), half = width / 2;
  const double global_step = number(main, "profil steps length").value_or(0.0);
  static const char* kSide[2] = {"Right Side", "Left Side"};
  static const char* kBorder[2] = {"Right Border", "Left Border"};
  double side_end[2], border[2];
  static const char* kPrefix[2] = {"r", "l"};
  // A side's or border's value `key` in `node` (the main track or a
  // segment), in either generation of the format.
  const auto side_value = [&](const pugi::xml_node& node, int k, bool is_border, const char* key) {
    if (v3) return number(node, (std::string(kPrefix[k]) + (is_border ? "border " : "side ") + key).c_str());
    return number(child_section(node, is_border ? kBorder[k] : kSide[k]), key);
  };
  for (int k = 0; k < 2; ++k) {
    side_end[k] = side_value(main, k, false, "width").value_or(0.0);
    border[k] = side_value(main, k, true, "width").value_or(0.0);
  }
  double x = 0, y = half, alf = 0;  // centre line position and heading
  double xmin = 0, ymin = 0;
  std::vector<std::pair<double, double>> centre{{x, y}};
  // Records a centre line point and the outer edges of both sides there.
  auto visit = [&](double px, double py, double heading, const double(&outer)[2]) {
    const double nx = -std::sin(heading), ny = std::cos(heading);  // towards the left
    for (int k = 0; k < 2; ++k) {
      const double d = (k == 1 ? 1.0 : -1.0) * (half + outer[k]);
      xmin = std::min(xmin, px + d * nx);
      ymin = std::min(ymin, py + d * ny);
    }
    centre.push_back({px, py});
  };
  for (const pugi::xml_node seg : segments.children("section")) {
    const std::string type = seg.find_child_by_attribute("attstr", "name", "type").attribute("val").as_string("");
    double length = 0, radius = 0, radius_end = 0, arc = 0;
    if (type == "str") {
      length = number(seg, "lg").value_or(0.0);
      if (!(length > 0 && length < 1e5)) throw bad(seg, "is a straight without a valid length");
    } else if (type == "lft" || type == "rgt") {
      radius = number(seg, "radius").value_or(0.0);
      radius_end = number(seg, "end radius").value_or(radius);
      arc = number(seg, "arc").value_or(0.0);
      if (!(radius > half && radius_end > half && arc > 0 && arc < 100 && radius < 1e5 && radius_end < 1e5))
        throw bad(seg, "is a turn without a valid radius and arc");
      length = (radius + radius_end) / 2 * arc;
    } else {
      throw bad(seg, "has unknown type '" + type + "'");
    }
    double side_start[2];
    for (int k = 0; k < 2; ++k) {
      const double sw = side_value(seg, k, false, "start width").value_or(side_end[k]);
      const double w = side_value(seg, k, false, "width").value_or(sw);
      side_start[k] = sw;
      side_end[k] = side_value(seg, k, false, "end width").value_or(w);
      border[k] = side_value(seg, k, true, "width").value_or(border[k]);
    }
    const std::string profile = seg.find_child_by_attribute("attstr", "name", "profil").attribute("val").as_string("spline");
    // Counted in double and checked before it becomes an int (a converted
    // out-of-range double is undefined behaviour, fuzzing found).
    double step_count = 1;
    if (profile == "spline") {
      step_count = std::floor(number(seg, "profil steps").value_or(1.0));
      if (step_count == 1) {
        const double step_length = number(seg, "profil steps length").value_or(global_step);
        step_count = step_length > 0 ? std::floor(length / step_length) + 1 : 1;
      }
    }
    if (!(step_count >= 1 && step_count <= 100000)) throw bad(seg, "has an unusable number of profile steps");
    const int steps = int(step_count);
    double step_length = length / steps, step_arc = arc / steps, dradius = (radius_end - radius) / steps;
    if (radius_end != radius && steps != 1) {
      dradius = (radius_end - radius) / (steps - 1);
      double angle = 0, rr = radius;
      for (int k = 0; k < steps; ++k) {
        angle += step_length / rr;
        rr += dradius;
      }
      step_length *= arc / angle;
    }
    for (int k = 0; k < steps; ++k) {
      if (dradius != 0) step_arc = step_length / radius;
      const double sign = type == "lft" ? 1.0 : -1.0;
      // Turn centre, `radius` to the inside of the centre line.
      const double cx = x - sign * radius * std::sin(alf), cy = y + sign * radius * std::cos(alf);
      const double a0 = alf;
      // A centre line point a metre; a track is kilometres long, so a
      // description whose segments add up to more is refused before the
      // points are made (a 23 KB file once asked for gigabytes).
      const double metres = std::ceil(type == "str" ? step_length : step_arc * radius);
      if (!(metres < kMaxTrackMetres - double(centre.size())))
        throw Error("track description '" + xml_path + "' describes a centre line over " +
                    std::to_string(int(kMaxTrackMetres / 1000)) + " km long (segment '" + seg.attribute("name").as_string() +
                    "')");
      const int n = std::max(1, int(metres));
      for (int i = 1; i <= n; ++i) {
        const double f = double(i) / n;
        double outer[2];
        for (int s2 = 0; s2 < 2; ++s2) {
          const double ks = (side_end[s2] - side_start[s2]) / steps;
          outer[s2] = border[s2] + side_start[s2] + (k + f) * ks;
        }
        if (type == "str") {
          visit(x + step_length * f * std::cos(alf), y + step_length * f * std::sin(alf), alf, outer);
        } else {
          const double a = a0 + sign * step_arc * f;
          visit(cx + sign * radius * std::sin(a), cy - sign * radius * std::cos(a), a, outer);
        }
      }
      x = centre.back().first;
      y = centre.back().second;
      if (type != "str") {
        alf = a0 + sign * step_arc;
        radius += dradius;
      }
    }
  }
  if (centre.size() < 2) throw Error("track description '" + xml_path + "' has no segments");
  std::vector<Vec3> line;
  line.reserve(centre.size());
  // TORCS's (x, y) ground plane, z up, becomes oovr's (x, -z) with y up.
  for (const auto& [cx, cy] : centre) line.push_back({float(cx - xmin), 0, float(-(cy - ymin))});
  return line;
}

Scene load_torcs_track(const std::string& name) {
  const auto tracks = list_torcs_tracks();
  const auto it = std::find_if(tracks.begin(), tracks.end(), [&](const TorcsTrack& t) { return t.name == name; });
  if (it == tracks.end())
    throw NotFoundError("no TORCS track '" + name + "' under " + torcs_directory() + "/tracks (" + std::to_string(tracks.size()) +
                        " installed; 'oovr scenes' lists them)");
  const fs::path dir = it->directory;
  std::error_code ec;
  fs::path model = dir / (name + ".acc");
  if (!fs::is_regular_file(model, ec)) model = dir / (name + ".ac");
  Ac3dOptions opt;
  opt.texture_dirs = {dir.string(), (fs::path(torcs_directory()) / "data" / "textures").string(),
                      (fs::path(torcs_directory()) / "data" / "img").string()};
  Scene scene = load_ac3d_file(model.string(), opt);
  scene.name = "torcs:" + name;
  scene.description = "TORCS " + it->category + " track " + name;

  // Camera: 120 frames spaced evenly along the centre line, at a driver's
  // eye height (1.1 m) over the road, looking 20 m ahead.
  const std::vector<Vec3> line = torcs_centre_line((dir / (name + ".xml")).string());
  const int frames = 120;
  const size_t n = line.size();
  float road = 0;
  bool have_road = false;
  int found = 0;
  CameraPath& cam = scene.camera;
  cam.fov_y_degrees = 70.0f;
  cam.z_near = 0.1f;
  cam.z_far = 2000.0f;
  for (int f = 0; f < frames; ++f) {
    const size_t i = size_t(uint64_t(f) * (n - 1) / frames);
    const Vec3 p = line[i], ahead = line[(i + 20) % n];
    const std::vector<float> h = heights_at(scene, p.x, p.z);
    if (!h.empty()) {
      // The surface nearest to the last road height (bridges pass over the
      // road); at the start, the highest.
      float best = have_road ? h[0] : *std::max_element(h.begin(), h.end());
      if (have_road)
        for (float y : h)
          if (std::abs(y - road) < std::abs(best - road)) best = y;
      road = best;
      have_road = true;
      ++found;
    }
    CameraPose pose;
    pose.position = {p.x, road + 1.1f, p.z};
    pose.target = {ahead.x, road + 1.1f, ahead.z};
    cam.frames.push_back(pose);
  }
  if (found < frames / 2)
    throw Error("TORCS track '" + name + "': the centre line computed from " + name + ".xml does not lie on the model (" +
                std::to_string(found) + " of " + std::to_string(frames) + " frames over a surface)");
  scene.notes.push_back("camera: 120 frames along the " + std::to_string(int(n - 1)) + " m centre line, " +
                        std::to_string(found) + " over the road surface");
  scene.validate();
  return scene;
}

namespace {

std::vector<SceneListing> list_tracks() {
  std::vector<SceneListing> out;
  for (const auto& t : list_torcs_tracks()) out.push_back({"torcs:" + t.name, "torcs", "TORCS " + t.category + " track"});
  return out;
}

const SceneSources::Add reg("torcs", {"torcs", "torcs:TRACK", true, 0, list_tracks, nullptr,
                                      [](const std::string& spec, const std::string& track, const SceneOptions& options) {
                                        if (!options.empty())
                                          unknown_scene_option(options.begin()->first, spec, "TORCS tracks take none");
                                        return load_torcs_track(track);
                                      },
                                      torcs_directory});

}  // namespace
}  // namespace oovr
