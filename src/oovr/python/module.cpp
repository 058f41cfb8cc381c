// _oovr: the native part of the oovr Python module (docs/python.md), a thin
// binding of the library. What the CLI does through its commands, Python
// does here through the same library calls (run_simulation, the sweep
// engine, the results document), so the two give the same numbers; the
// pure-Python package (oovr/_api.py, exported by oovr/__init__.py) wraps these into result objects and
// DataFrames.
//
// Scenes and traces are held by one TraceSession for the interpreter's
// life: a loop over configurations loads each scene once and renders each
// frame once. Long calls release the GIL; the library's errors become
// Python exceptions (NotFoundError: FileNotFoundError, UnknownKeyError:
// KeyError, any other Error: ValueError, std::bad_alloc: MemoryError).
//
// Several Python threads may call in at once (a call without the GIL lets
// them run): nothing here waits for another thread while holding the GIL
// (see numpy_ready).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <optional>

#include "bindings.h"
#include "oovr/core/config_sections.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/version.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/sweep.h"
#include "oovr/experiments/sweep_run.h"
#include "oovr/pipeline/frame_summary.h"
#include "oovr/pipeline/image.h"
#include "oovr/run/result_images.h"
#include "oovr/run/result_json.h"
#include "oovr/run/result_metrics.h"
#include "oovr/run/result_text.h"
#include "oovr/run/session.h"
#include "oovr/run/simulation.h"
#include "oovr/scene/load.h"
#include "oovr/scene/scene_info.h"

namespace oovr::python {

py::object to_python(const nlohmann::ordered_json& j) { return py::module_::import("json").attr("loads")(j.dump()); }

std::string type_name(const py::handle& v) { return py::str(py::type::of(v).attr("__name__")).cast<std::string>(); }

py::object as_int(const py::handle& v) {
  if (PyBool_Check(v.ptr())) return {};
  if (PyLong_Check(v.ptr())) return py::reinterpret_borrow<py::object>(v);
  if (!PyIndex_Check(v.ptr())) return {};
  PyObject* i = PyNumber_Index(v.ptr());
  if (!i) {
    PyErr_Clear();
    return {};
  }
  return py::reinterpret_steal<py::object>(i);
}

int64_t whole(const py::handle& v, const std::string& what) {
  const py::object i = as_int(v);
  if (!i) throw py::type_error(what + " must be an int, not " + type_name(v));
  int overflow = 0;
  const long long n = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow) throw Error(what + " is " + py::repr(v).cast<std::string>() + ", past any count oovr takes");
  return n;
}

namespace {

namespace fs = std::filesystem;

// The interpreter's scenes and traces. Never destroyed: it may hold
// gigabytes that the process's exit frees faster, and nothing in it refers
// to Python objects. Made when the module is imported (PYBIND11_MODULE),
// so that no thread ever waits here for another to make it.
TraceSession& session() {
  static TraceSession* s = new TraceSession();
  return *s;
}

// pybind11 (2.10) looks numpy's C API up when the module makes its first
// array, in a function-local static (npy_api::get) whose initialisation
// imports numpy. An import lets other threads take the GIL; one that makes
// its first array then waits for that static while holding the GIL, which
// the importing thread needs back: both wait forever. So every array is
// made after numpy_ready(), which does the lookup once, and a thread that
// finds another doing it waits without the GIL.
std::atomic<bool> g_numpy_ready{false};
std::mutex g_numpy_lookup;

void numpy_ready() {
  if (g_numpy_ready.load(std::memory_order_acquire)) return;
  py::gil_scoped_release release;  // wait for another thread's lookup without the GIL
  std::lock_guard<std::mutex> lock(g_numpy_lookup);
  if (g_numpy_ready.load(std::memory_order_acquire)) return;
  py::gil_scoped_acquire gil;  // the lookup imports numpy: under the GIL, here alone
  (void)py::detail::npy_api::get();
  g_numpy_ready.store(true, std::memory_order_release);
}

// ----- scenes

struct PyScene {
  std::string spec;  // what load_scene was given
  std::shared_ptr<const Scene> scene;
  SceneInfo info;
};

PyScene load(const std::string& spec) {
  PyScene s;
  s.spec = spec;
  {
    py::gil_scoped_release release;
    s.scene = session().scene(spec);
    s.info = scene_info(*s.scene);
  }
  return s;
}

// A scene argument: a name (str) or a Scene from load_scene.
std::string scene_spec(const py::handle& scene) {
  if (py::isinstance<py::str>(scene)) return scene.cast<std::string>();
  if (py::isinstance<PyScene>(scene)) return scene.cast<const PyScene&>().spec;
  throw py::type_error("scene must be a name (str) or a Scene from oovr.load_scene, not " + type_name(scene));
}

// ----- configurations

// A Python value as Config::set takes it ("128GBps", "8", "true", "0.5").
std::string config_text(const std::string& key, const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) {
    const double d = v.cast<double>();
    if (!std::isfinite(d)) throw Error("configuration key '" + key + "': " + py::repr(v).cast<std::string>() + " is not finite");
    return py::repr(v).cast<std::string>();
  }
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  throw py::type_error("configuration key '" + key + "' takes a str, int, float or bool, not " + type_name(v));
}

// Sets `key` to `v` on a copy, checks the whole configuration and keeps it
// only when it is good, so a bad set() leaves the Config as it was.
// The value's source is the Config's: "oovr.config" for the user's, "scheme
// NAME" for the copy a Python scheme's configure() is given.
void set_checked(Config& c, const std::string& key, const py::handle& v) {
  Config next = c;
  next.set(key, config_text(key, v));
  check_config(next);
  c = std::move(next);
}

Config make_config(const std::optional<std::string>& preset, const py::dict& overrides) {
  Config c = preset ? Config::from_toml_file(*preset) : Config{};
  c.set_source("oovr.config");
  for (const auto& [k, v] : overrides) {
    if (!py::isinstance<py::str>(k))
      throw py::type_error("overrides: a configuration key is a str ('link.bandwidth'), not " + type_name(k) + " " +
                           py::repr(k).cast<std::string>());
    const std::string key = k.cast<std::string>();
    c.set(key, config_text(key, v));
  }
  check_config(c);
  return c;
}

py::dict entry_dict(const Config::Entry& e) {
  py::dict d;
  d["value"] = e.value;
  d["default"] = e.fallback;
  d["source"] = e.source;
  d["takes"] = e.kind;
  d["unit"] = e.unit.empty() ? py::object(py::none()) : py::object(py::str(e.unit));
  d["base"] = e.base ? py::object(py::float_(*e.base)) : py::object(py::none());
  return d;
}

const Config::Entry& entry(const Config& c, const std::string& key) {
  const auto it = c.entries().find(key);
  if (it == c.entries().end()) throw UnknownKeyError("unknown configuration key '" + key + "' ('oovr config --all' lists them)");
  return it->second;
}

// ----- images

// An image as a NumPy array, top row first (oovr's images are bottom row
// first, as OpenGL reads them).
py::array_t<uint8_t> image_array(const Image& img) {
  numpy_ready();
  py::array_t<uint8_t> a({size_t(img.height), size_t(img.width), size_t(4)});
  auto* out = a.mutable_data();
  const size_t row = size_t(img.width) * 4;
  for (int y = 0; y < img.height; ++y)
    std::copy_n(img.rgba.data() + size_t(img.height - 1 - y) * row, row, out + size_t(y) * row);
  return a;
}

struct PyFrame {
  std::shared_ptr<const FrameOutput> out;
  FrameSummary summary;
};

py::dict summary_dict(const FrameSummary& s) {
  py::dict d;
  d["frame"] = s.frame;
  d["resolution"] = std::to_string(s.frame_width) + "x" + std::to_string(s.frame_height);
  d["draws"] = s.draws;
  d["triangles_set_up"] = py::make_tuple(s.setup[0], s.setup[1]);
  d["triangles_culled"] = s.culled;
  d["fragments_covered"] = s.covered;
  d["fragments_shaded"] = s.shaded;
  d["fragments_passed"] = s.passed;
  d["quads"] = s.quads;
  d["records"] = s.records;
  d["texture_line_reads"] = s.texture_line_reads;
  d["line_bytes"] = s.line_bytes;
  d["pixels_drawn"] = s.pixels_drawn;
  d["layer_fetches"] = s.layer_fetches;
  d["layers_per_shaded_fragment"] = s.layers_per_shaded();
  d["layers_per_pixel_drawn"] = s.layers_per_pixel();
  d["texture_bytes_touched"] = s.texture_bytes_touched;
  return d;
}

// `resolution` (the whole side-by-side frame; default 1280x1024) or
// `eye_resolution` (one eye's), as the CLI's --resolution and
// --eye-resolution: giving both is an error, not one silently winning.
StereoRig rig_of(const std::optional<std::string>& resolution, const std::optional<std::string>& eye_resolution) {
  if (resolution && eye_resolution)
    throw Error("give resolution or eye_resolution, not both (resolution '" + *resolution + "', eye_resolution '" +
                *eye_resolution + "')");
  return eye_resolution ? parse_eye_resolution(*eye_resolution) : parse_frame_resolution(resolution.value_or("1280x1024"));
}

// ----- simulation

py::dict simulate(const py::handle& scene, const py::list& schemes, const std::optional<Config>& config, int frames, int frame,
                  const std::optional<std::string>& resolution, const std::optional<std::string>& eye_resolution, int aniso,
                  bool cache, bool images, unsigned jobs, const std::string& command) {
  SimulationRequest r;
  r.scene = scene_spec(scene);
  r.rig = rig_of(resolution, eye_resolution);
  if (frames < 0) throw Error("frames " + std::to_string(frames) + ": give a positive number, or None for one per GPM");
  if (frame < 0) throw Error("frame " + std::to_string(frame) + " is out of range: frames are numbered from 0");
  if (aniso < 1 || aniso > 16) throw Error("aniso " + std::to_string(aniso) + ": anisotropic taps are 1 to 16");
  r.frame = frame;
  r.frames = frames;
  r.aniso = aniso;
  r.use_cache = cache;
  r.need_first_image = images;
  r.jobs = jobs;
  r.frames_option = "frames";
  std::vector<SchemeRef> refs;
  for (const auto& s : schemes) refs.push_back(scheme_of(s));
  // A Python scheme's results carry its name: two of one name in a call
  // could not be told apart (scheme_of has refused registered names).
  for (size_t i = 0; i < refs.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (refs[i].name == refs[j].name && !py::isinstance<py::str>(schemes[i]))
        throw Error("two schemes named '" + refs[i].name + "' in one call (schemes " + std::to_string(j) + " and " +
                    std::to_string(i) + "): their results would carry one name; give each Python scheme a name of its own");
  const Config machine = config.value_or(Config{});
  Simulation sim;
  {
    py::gil_scoped_release release;  // schemes written in Python take it back while they run
    sim = run_simulation(r, refs, machine, cache ? &session() : nullptr);
  }
  py::dict out;
  out["document"] = to_python(results_document(command, sim.window->scene->name, sim.frame, sim.frames, sim.window->rig, machine,
                                               sim.results, sim.window->notes));
  py::list texts;
  for (size_t i = 0; i < sim.results.size(); ++i) texts.append(simulation_text(sim, i));
  out["simulate_text"] = texts;
  out["compare_text"] = comparison_text(sim);
  out["timing_text"] = timing_text(sim);
  out["trace_seconds"] = sim.trace_s;
  out["simulation_seconds"] = sim.simulation_s;
  py::list rows;
  for (const ComparisonRow& c : comparison_rows(sim.results)) {
    py::dict d;
    d["scheme"] = c.scheme;
    d["latency ms"] = c.latency_ms;
    d["speed-up"] = c.speedup;
    d["frames/s"] = c.frames_per_s;
    d["throughput"] = c.throughput_ratio;
    d["inter-GPM MB"] = c.inter_gpm_mb;
    d["traffic"] = c.traffic_ratio;
    d["best/worst"] = c.best_to_worst;
    d["energy mJ"] = c.energy_mj;
    rows.append(d);
  }
  out["rows"] = rows;
  py::list metrics, pictures;
  for (const SchemeResult& res : sim.results) {
    py::list m;
    for (const Metric& x : metrics_of(res)) m.append(py::make_tuple(x.location, x.metric, x.value, x.unit));
    metrics.append(m);
    py::dict p;
    const FrameOutput& first = sim.window->outputs.front();
    if (images && !first.colour.rgba.empty()) {
      p["gpm"] = image_array(gpm_image(first, res));
      p["traffic"] = image_array(traffic_image(first, res));
    }
    pictures.append(p);
  }
  out["metrics"] = metrics;
  out["images"] = pictures;
  return out;
}

// ----- sweeps

// A point's record as the progress callback gets it; `total`: the points
// this sweep runs.
py::dict record_dict(const RunRecord& r, size_t total) {
  py::dict d;
  d["total"] = total;
  d["id"] = r.id;
  d["sweep"] = r.sweep;
  d["position"] = r.position;
  d["scene"] = r.scene;
  d["scheme"] = r.scheme;
  d["resolution"] = r.resolution;
  d["status"] = r.status;
  d["error"] = r.error;
  d["wall_s"] = r.wall_s;
  d["swept"] = to_python(nlohmann::ordered_json(r.swept));
  d["settings"] = swept_text(r);
  return d;
}

py::dict sweep(const std::string& text, const std::string& name, const std::string& base_dir, const std::string& db_path,
               bool resume, bool retry_failed, bool reconcile, unsigned jobs, bool cache, const std::string& command,
               const py::object& on_record, const py::object& on_status) {
  Sweep s = parse_sweep(text, name, base_dir);
  resolve_all(s);
  ResultsDb db(db_path);  // the one writer
  db.verify();            // whole, before anything is added to it or kept
  const SweepPlan plan = plan_sweep(s, db, resume, retry_failed, reconcile);
  begin_sweep(s, plan, db, command);
  size_t done = 0, failed = 0;
  SweepRunOptions o;
  o.jobs = jobs;
  o.use_cache = cache;
  o.command = command;
  // Called one at a time, from worker threads, once run_points_into has
  // stored the record: a callback that raises loses nothing.
  std::optional<py::error_already_set> raised;
  o.on_record = [&](const RunRecord& r) {
    ++(r.status == "done" ? done : failed);
    py::gil_scoped_acquire gil;
    if (raised || on_record.is_none()) return;
    try {
      on_record(record_dict(r, plan.todo.size()));
    } catch (py::error_already_set& e) {
      raised = std::move(e);
    }
  };
  o.on_status = [&](const std::string& line) {
    py::gil_scoped_acquire gil;
    if (raised || on_status.is_none()) return;
    try {
      on_status(line);
    } catch (py::error_already_set& e) {
      raised = std::move(e);
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  {
    py::gil_scoped_release release;
    run_points_into(s, plan.todo, db, o);
  }
  if (raised) throw std::move(*raised);
  py::dict out;
  out["name"] = s.name;
  out["db"] = db_path;
  out["points"] = s.points.size();
  out["held"] = plan.held;
  out["run"] = plan.todo.size();
  out["done"] = done;
  out["failed"] = failed;
  out["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out["notes"] = plan.notes;
  return out;
}

}  // namespace

}  // namespace oovr::python

using namespace oovr;
using namespace oovr::python;

PYBIND11_MODULE(_oovr, m) {
  m.doc() = "The native part of the oovr Python module; import oovr, not this (docs/python.md).";

  (void)session();

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const NotFoundError& e) {
      PyErr_SetString(PyExc_FileNotFoundError, e.what());
    } catch (const UnknownKeyError& e) {
      PyErr_SetString(PyExc_KeyError, e.what());
    } catch (const Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  m.def("version", &version, "oovr's version, as `oovr --version` prints it.");
  m.def("git_commit", &git_commit, "The git commit oovr was built from.");

  m.def(
      "scenes",
      [] {
        py::list out;
        for (const SceneListing& s : list_scenes()) {
          py::dict d;
          d["name"] = s.name;
          d["kind"] = s.kind;
          d["description"] = s.description;
          out.append(d);
        }
        return out;
      },
      "Every scene load_scene accepts by name (built-in and installed game levels), as `oovr scenes` lists them: "
      "a list of dicts with name, kind and description.");
  m.def(
      "schemes",
      [] {
        py::dict out;
        for (const auto& n : Schemes::names()) out[py::str(n)] = Schemes::find(n)->description;
        return out;
      },
      "Every registered scheme with its description, as `oovr schemes` lists them.");
  m.def("default_compare_schemes", &default_compare_schemes,
        "The schemes `oovr compare` runs by default: the paper's, in the paper's order, then the bounds and the rest.");

  py::class_<PyScene>(m, "Scene", "A loaded scene: its draws, triangles, textures and their sharing (as `oovr scene-info`).")
      .def_property_readonly(
          "name", [](const PyScene& s) { return s.scene->name; }, "The scene's name.")
      .def_property_readonly(
          "spec", [](const PyScene& s) { return s.spec; }, "What it was loaded as (a name, a path, 'oa:MAP?...').")
      .def_property_readonly(
          "draws", [](const PyScene& s) { return s.info.draws; }, "Objects, each one draw per eye.")
      .def_property_readonly(
          "triangles", [](const PyScene& s) { return s.info.triangles; }, "Triangles over every draw.")
      .def_property_readonly(
          "vertices", [](const PyScene& s) { return s.info.vertices; }, "Mesh vertices.")
      .def_property_readonly(
          "textures", [](const PyScene& s) { return s.info.textures; }, "Distinct textures.")
      .def_property_readonly(
          "texture_bytes", [](const PyScene& s) { return s.info.texture_bytes; }, "Bytes of every texture with its mip chain.")
      .def_property_readonly(
          "camera_frames", [](const PyScene& s) { return s.info.camera_frames; }, "Frames of the camera path.")
      .def_property_readonly(
          "sharing", [](const PyScene& s) { return s.info.sharing_histogram; },
          "Objects per texture -> how many textures that many objects share.")
      .def_property_readonly(
          "max_sharing", [](const PyScene& s) { return s.info.max_sharing; }, "Most objects sharing one texture.")
      .def_property_readonly(
          "notes", [](const PyScene& s) { return s.scene->notes; }, "What the loader reported.")
      .def(
          "info", [](const PyScene& s) { return to_python(scene_info_json(s.info, s.scene->notes)); },
          "Everything `oovr scene-info --json` prints, as a dict (with every texture and the objects sampling it).")
      .def("__repr__", [](const PyScene& s) {
        return "<oovr.Scene " + s.scene->name + ": " + std::to_string(s.info.draws) + " draws, " +
               std::to_string(s.info.triangles) + " triangles, " + std::to_string(s.info.textures) + " textures>";
      });
  m.def("load_scene", &load, py::arg("name"),
        "Loads a scene by name ('courtyard', 'oa:oa_dm4', a model file's path); the session keeps it, so loading it "
        "again costs nothing. FileNotFoundError when its file or game data is not there, ValueError for an unknown "
        "name or a bad file.");

  py::class_<Config>(m, "Config",
                     "A machine configuration: a preset (default: the paper's Table 1) with overrides, every key checked "
                     "as the CLI checks --set. Make one with oovr.config().")
      .def(py::init(&make_config), py::arg("preset") = py::none(), py::arg("overrides") = py::dict(),
           "A preset (a TOML file; None: the paper's Table 1) with overrides {key: value}. KeyError for an unknown key, "
           "ValueError for a bad value, FileNotFoundError for a missing preset.")
      .def(
          "set", [](Config& c, const std::string& key, const py::handle& v) { set_checked(c, key, v); }, py::arg("key"),
          py::arg("value"), "Sets one key (checked; the Config is unchanged when it raises).")
      .def(
          "get", [](const Config& c, const std::string& key) { return entry(c, key).value; }, py::arg("key"),
          "The value in force, readable ('64 GB/s'); KeyError for an unknown key.")
      .def(
          "__getitem__", [](const Config& c, const std::string& key) { return entry(c, key).value; }, py::arg("key"))
      .def(
          "__contains__", [](const Config& c, const std::string& key) { return c.entries().count(key) != 0; }, py::arg("key"))
      .def(
          "keys",
          [](const Config& c) {
            std::vector<std::string> k;
            for (const auto& [key, e] : c.entries()) k.push_back(key);
            return k;
          },
          "Every key any component reads, sorted.")
      .def(
          "entries",
          [](const Config& c) {
            py::dict d;
            for (const auto& [k, e] : c.entries()) d[py::str(k)] = entry_dict(e);
            return d;
          },
          "Every key with value, default, source, what it takes, unit and the value in that unit (base), as `oovr config "
          "--all` lists them.")
      .def("to_toml", &resolved_toml, "Every value in force as TOML: a preset that reads back as this configuration.")
      .def(
          "copy", [](const Config& c) { return c; }, "A copy to change without changing this one.")
      .def("__copy__", [](const Config& c) { return c; })
      .def(
          "__deepcopy__", [](const Config& c, const py::dict&) { return c; }, py::arg("memo"))
      .def("__repr__", [](const Config& c) {
        std::string set;
        for (const auto& [k, e] : c.entries())
          if (e.source != "default") set += (set.empty() ? "" : ", ") + k + "=" + e.value;
        return "<oovr.Config" + (set.empty() ? std::string(": the paper's Table 1") : ": " + set) + ">";
      });

  py::class_<PyFrame>(m, "Frame", "A rendered stereo frame: the image, which object drew each pixel, and the trace's figures.")
      .def_property_readonly(
          "image", [](const PyFrame& f) { return image_array(f.out->colour); },
          "The side-by-side stereo image, an (height, width, 4) uint8 RGBA array, top row first.")
      .def_property_readonly(
          "object_id",
          [](const PyFrame& f) {
            numpy_ready();
            const int w = f.out->colour.width, h = f.out->colour.height;
            py::array_t<uint32_t> a({size_t(h), size_t(w)});
            for (int y = 0; y < h; ++y)
              std::copy_n(f.out->object_id.data() + size_t(h - 1 - y) * size_t(w), size_t(w),
                          a.mutable_data() + size_t(y) * size_t(w));
            return a;
          },
          "Per pixel, the object that last wrote it (0xffffffff: none), an (height, width) uint32 array, top row first.")
      .def_property_readonly(
          "summary", [](const PyFrame& f) { return summary_dict(f.summary); },
          "What the frame amounts to, as `oovr render` prints it: draws, triangles set up and culled, fragments "
          "covered, shaded and passed, trace records, texture line reads and texture layers per fragment.")
      .def(
          "save", [](const PyFrame& f, const std::string& path) { write_image(f.out->colour, path); }, py::arg("path"),
          "Writes the image (.png, .ppm or .jpg by the path's extension).")
      .def("__repr__", [](const PyFrame& f) {
        return "<oovr.Frame " + std::to_string(f.summary.frame) + ", " + std::to_string(f.summary.frame_width) + "x" +
               std::to_string(f.summary.frame_height) + ", " + std::to_string(f.summary.records) + " records>";
      });
  m.def(
      "render",
      [](const py::handle& scene, int frame, const std::optional<std::string>& resolution,
         const std::optional<std::string>& eye_resolution, int aniso, float ipd_mm) {
        const std::string spec = scene_spec(scene);
        StereoRig rig = rig_of(resolution, eye_resolution);
        if (!(ipd_mm >= 0 && ipd_mm <= 1000))
          throw Error("ipd_mm must be from 0 to 1000 (millimetres between the eyes), not " + std::to_string(ipd_mm));
        rig.ipd_m = ipd_mm / 1000.0f;
        PipelineSettings settings;
        settings.max_anisotropy = aniso;
        settings.validate();
        PyFrame f;
        {
          py::gil_scoped_release release;
          const auto sc = session().scene(spec);
          if (frame < 0 || frame >= int(sc->camera.frames.size()))
            throw Error("frame " + std::to_string(frame) + " is out of range: the camera path has " +
                        std::to_string(sc->camera.frames.size()) + " frames");
          f.out =
              std::make_shared<const FrameOutput>(render_frame(*sc, make_stereo_view(sc->camera, frame, rig), settings, frame));
          f.summary = summarise(*f.out);
        }
        return f;
      },
      py::arg("scene"), py::arg("frame") = 0, py::arg("resolution") = py::none(), py::arg("eye_resolution") = py::none(),
      py::arg("aniso") = 16, py::arg("ipd_mm") = 64.0f,
      "Renders frame `frame` of a scene's camera path in stereo, as `oovr render` does: returns a Frame. `resolution` "
      "is the whole side-by-side frame (default 1280x1024), `eye_resolution` one eye's; give one, not both.");

  m.def("_simulate", &simulate, py::arg("scene"), py::arg("schemes"), py::arg("config"), py::arg("frames"), py::arg("frame"),
        py::arg("resolution"), py::arg("eye_resolution"), py::arg("aniso"), py::arg("cache"), py::arg("images"), py::arg("jobs"),
        py::arg("command"), "oovr.simulate and oovr.compare's native part.");
  m.def(
      "_sweep_toml",
      [](const py::object& definition) {
        std::string text;
        try {
          text = py::module_::import("json").attr("dumps")(definition, py::arg("allow_nan") = false).cast<std::string>();
        } catch (py::error_already_set& e) {
          if (!e.matches(PyExc_ValueError)) throw;
          throw Error("sweep definition: " + std::string(py::str(e.value())) +
                      " (NaN and infinities are not values a sweep takes)");
        }
        return sweep_toml(nlohmann::json::parse(text));
      },
      py::arg("definition"), "A sweep definition (a dict) as the text of a sweep file.");
  m.def(
      "_read_sweep", [](const std::string& path) { return read_input_file(path, "sweep", uint64_t(1) << 20); }, py::arg("path"),
      "A sweep file's text, read as `oovr sweep` reads it (a regular file of at most 1 MiB).");
  m.def("_sweep", &sweep, py::arg("text"), py::arg("name"), py::arg("base_dir"), py::arg("db"), py::arg("resume"),
        py::arg("retry_failed"), py::arg("reconcile"), py::arg("jobs"), py::arg("cache"), py::arg("command"),
        py::arg("on_record"), py::arg("on_status"), "oovr.sweep's native part.");
  m.def(
      "_verify_db",
      [](const std::string& path) {
        const ResultsDb db(path, ResultsDb::Access::read_only);
        db.verify();
      },
      py::arg("db"), "Checks a results database whole (ResultsDb::verify), read-only.");
  m.def(
      "trace_stats",
      [] {
        const TraceSession::Stats s = session().stats();
        py::dict d;
        d["scenes_loaded"] = s.scenes_loaded;
        d["frames_rendered"] = s.frames_rendered;
        d["frames_from_disk"] = s.frames_from_disk;
        d["windows_reused"] = s.windows_reused;
        d["windows_held"] = s.windows_held;
        d["bytes_held"] = s.bytes_held;
        return d;
      },
      "What the session has done: scenes loaded, frames rendered, traces read from the disk cache, requests answered "
      "from memory, and the windows and bytes of traces it holds now.");
  m.def(
      "clear_traces",
      [] {
        py::gil_scoped_release release;  // the session's lock may be held by a thread loading traces
        session().clear();
      },
      "Drops every scene and trace the session holds (the disk cache stays).");

  bind_schemes(m);
}
