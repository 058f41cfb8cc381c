// Schemes written in Python (docs/python.md, "Schemes in Python"): a Python
// object with run(input) decides which GPM does which work in which order
// and how the frame is composed, through the same FrameSim calls a C++
// scheme makes (schemes/frame_sim.h, schemes/composition.h); oovr's C++
// replays every memory access and runs the timing model. A Python scheme
// making the calls a C++ scheme makes gets its numbers exactly
// (examples/object_level.py and tests/python/test_schemes.py).
//
// What Python holds of a run (the input, the FrameSim, records, jobs, the
// composer) is valid only while its run() runs: each holds the run's token
// and raises RuntimeError once the run is over, instead of reading freed
// traces. Arguments are checked (GPMs, objects, framebuffers, units, and
// sizes against what the machine and the run's frames hold) before they
// reach the C++, so a mistake is a TypeError (a wrong type) or a ValueError
// naming the call and the parameter ("transfer(bytes=...): ..."), never a
// crash or a silent clamp.
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <optional>

#include "bindings.h"
#include "oovr/core/error.h"
#include "oovr/schemes/composition.h"
#include "oovr/schemes/frame_sim.h"
#include "oovr/schemes/sort_first.h"

namespace oovr::python {

namespace {

// One run of a Python scheme; what it hands out dies with it.
struct RunToken {
  bool alive = true;
};
using Token = std::shared_ptr<RunToken>;

void check_alive(const Token& t, const char* what) {
  if (!t || !t->alive)
    throw std::runtime_error(std::string(what) +
                             " belongs to a scheme run that has ended: keep nothing from run() after it returns");
}

[[noreturn]] void bad(const std::string& what) { throw Error(what); }

// How a message names an argument: "transfer(bytes=10): ".
std::string arg(const char* fn, const char* param, const std::string& value) {
  return std::string(fn) + "(" + param + "=" + value + "): ";
}
std::string arg(const char* fn, const char* param, int64_t value) { return arg(fn, param, std::to_string(value)); }

// A count or a size (draws, triangles, bytes, pixels): a whole number
// (as_int) from 0 to `most` (any int: one past 64 bits is refused as too
// many, not as the wrong type); `why()` says what bounds it, made only for
// a message.
template <class Why>
uint64_t count(const py::handle& v, const char* fn, const char* param, uint64_t most, const Why& why) {
  const py::object i = as_int(v);
  if (!i) throw py::type_error(std::string(fn) + "(" + param + "): " + param + " must be an int, not " + type_name(v));
  int overflow = 0;
  const long long n = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow < 0 || (!overflow && n < 0)) bad(arg(fn, param, py::repr(i).cast<std::string>()) + "cannot be negative");
  if (overflow > 0 || uint64_t(n) > most) bad(arg(fn, param, py::repr(i).cast<std::string>()) + "more than " + why());
  return uint64_t(n);
}

// What a scheme's function (an owner, a key; called per tile or record)
// returned, as an int: TypeError for what is not one. `what()` names the
// function for messages; it is made only for one.
template <class What>
int64_t returned_int(const py::handle& v, const What& what, const char* expected) {
  if (PyLong_CheckExact(v.ptr())) {  // the usual case, per tile or record: no conversion
    int overflow = 0;
    const long long n = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
    if (!overflow) return n;
  }
  const py::object i = as_int(v);
  if (!i) throw py::type_error(what() + " must return " + expected + ", not " + type_name(v));
  int overflow = 0;
  const long long n = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
  if (overflow) bad(what() + " gave " + py::repr(v).cast<std::string>() + ", past any count oovr takes");
  return n;
}

// A GPM an owner function returned: ValueError for one the machine lacks.
template <class What>
int returned_gpm(const py::handle& v, int gpms, const What& what) {
  const int64_t g = returned_int(v, what, "a GPM (int)");
  if (g < 0 || g >= gpms)
    bad(what() + " gave GPM " + std::to_string(g) + ", which does not exist (GPMs 0 to " + std::to_string(gpms - 1) + ")");
  return int(g);
}

// ----- traces

struct PyRecords {
  Token token;
  const FrameTrace* trace = nullptr;
  std::vector<const TileWork*> records;
};

struct PyRecord {
  Token token;
  const TileWork* r = nullptr;
  const TileWork& get() const {
    check_alive(token, "a Record");
    return *r;
  }
};

struct PyTrace {
  Token token;
  const FrameTrace* trace = nullptr;
  const FrameTrace& get() const {
    check_alive(token, "a Trace");
    return *trace;
  }
};

// ----- the run's input and its FrameSim

// Draws of the input's frame with the most (a captured game's frames draw
// different numbers of objects; other scenes draw the same in each).
size_t most_draws(const SchemeInput& in) {
  size_t n = in.scene->draws(0).size();
  for (const FrameTrace* f : in.frames)
    if (f) n = std::max(n, in.scene->draws(f->frame).size());
  return n;
}

struct PyInput {
  Token token;
  SchemeInput in;
  size_t objects() const {
    check_alive(token, "a SchemeInput");
    return most_draws(in);
  }
};

struct PySim {
  Token token;
  std::unique_ptr<FrameSim> sim;
  int framebuffers = 1;
  std::vector<const FrameTrace*> frames;
  size_t objects = 0;
  uint64_t dram_bytes = 0;  // one GPM's DRAM (dram.capacity): the most one transfer moves
  // The most a call may ask for, from what the run's frames hold (made
  // when first needed: a pass over the records).
  struct Bounds {
    uint64_t draws = 0;   // both views of every object of every frame
    uint64_t pixels = 0;  // what composition could merge: per record, its passed fragments or its tile's pixels, the more
    std::vector<uint64_t> triangles;  // per object, its most in a frame: set up in both eyes, or binned to its tiles
  };
  std::optional<Bounds> limits;
  // Work is added while building, and while finish() runs from its
  // on_finish; the engine runs once (an exception from on_finish ends it).
  enum class State { building, running, done } state = State::building;

  FrameSim& get() {
    check_alive(token, "a FrameSim");
    return *sim;
  }
  FrameSim& adding() {
    FrameSim& s = get();
    if (state == State::done) throw std::runtime_error("FrameSim.finish() has run: no more work can be added");
    return s;
  }
  const Bounds& bounds() {
    if (!limits) {
      Bounds b;
      b.draws = 2 * uint64_t(objects) * frames.size();
      b.triangles.assign(objects, 0);
      for (const FrameTrace* f : frames) {
        const uint64_t tile = uint64_t(f->tile_size) * uint64_t(f->tile_size);
        std::vector<uint64_t> binned(objects, 0);
        for (const TileWork& w : f->tiles) {
          b.pixels += std::max<uint64_t>(w.passed, tile);
          if (w.object < objects) binned[w.object] += w.triangles;
        }
        for (size_t o = 0; o < objects && o < f->objects.size(); ++o)
          b.triangles[o] = std::max({b.triangles[o], uint64_t(f->objects[o].setup[0]) + f->objects[o].setup[1], binned[o]});
      }
      limits = std::move(b);
    }
    return *limits;
  }
  // Python ints as the C++ ints FrameSim takes: what they name (a GPM, a
  // framebuffer, a unit) FrameSim checks, as it does for a C++ scheme; here
  // only that they fit.
  static int index(int64_t v, const char* fn, const char* param) {
    if (v < INT_MIN || v > INT_MAX) bad(arg(fn, param, v) + "out of range");
    return int(v);
  }
  static std::vector<int> units(const std::vector<int64_t>& after, const char* fn) {
    std::vector<int> out;
    for (int64_t u : after) {
      if (u < -1 || u > INT_MAX)
        bad(std::string(fn) + "(after): unit " + std::to_string(u) + " has not been added (-1 for none)");
      out.push_back(int(u));
    }
    return out;
  }
  // One unit that has been added (the engine's questions, which FrameSim
  // passes on unchecked).
  int unit(int64_t u, const char* fn, const char* param = "unit") const {
    const int64_t n = int64_t(sim->engine().units());
    if (u < 0 || u >= n)
      bad(arg(fn, param, u) + "unit " + std::to_string(u) + " has not been added (units 0 to " + std::to_string(n - 1) + ")");
    return int(u);
  }
  std::string dram_holds() const { return "one GPM's DRAM holds (dram.capacity: " + std::to_string(dram_bytes) + " bytes)"; }
  uint64_t bytes(const py::handle& v, const char* fn, const char* param) const {
    return count(v, fn, param, dram_bytes, [this] { return dram_holds(); });
  }
  uint32_t object(int64_t o, const char* fn) const {
    if (o < 0 || uint64_t(o) >= objects)
      bad(arg(fn, "object", o) + "object " + std::to_string(o) + " does not exist (objects 0 to " +
          std::to_string(int64_t(objects) - 1) + ")");
    return uint32_t(o);
  }
  const FrameTrace* own(const PyRecords& r, const char* what) const {
    check_alive(r.token, "a Records");
    if (r.token != token) throw std::runtime_error(std::string(what) + ": the records belong to another run");
    if (std::find(frames.begin(), frames.end(), r.trace) == frames.end())
      bad(std::string(what) + ": the records are not of this run's frames");
    return r.trace;
  }
};

// The triangles a geometry call sets up: a count up to what object `o` has
// in the run's frames (geometry and geometry_part check it alike).
uint64_t triangles_of(PySim& s, uint32_t o, const py::handle& triangles, const char* fn) {
  const uint64_t most = s.bounds().triangles[o];
  return count(triangles, fn, "triangles", most, [&] {
    return "object " + std::to_string(o) + " has in this run's frames (at most " + std::to_string(most) +
           ": set up in both eyes, or binned to its tiles)";
  });
}

struct PyJob {
  Token token;  // of the records, once set
  const FrameTrace* trace = nullptr;
  FrameSim::TileJob job;
};

struct PyComposer {
  std::shared_ptr<PySim> sim;
  std::unique_ptr<Composer> composer;
  Composer& get() {
    (void)sim->get();
    return *composer;
  }
};

struct PyResult {
  SchemeResult r;
};

// A positive, finite number of seconds or frames per second for a
// SchemeResult's `attr`: a float, an int or another real number (numpy's).
double positive(const py::handle& v, const char* attr, const char* what) {
  double x = 0;
  if (!PyBool_Check(v.ptr()) && PyNumber_Check(v.ptr()) && !PyComplex_Check(v.ptr())) {
    x = PyFloat_AsDouble(v.ptr());
    if (x == -1.0 && PyErr_Occurred()) {
      const bool too_big = PyErr_ExceptionMatches(PyExc_OverflowError);
      PyErr_Clear();
      if (!too_big) throw py::type_error(std::string(attr) + " must be a number (float), not " + type_name(v));
      x = HUGE_VAL;  // refused below, as infinite
    }
  } else {
    throw py::type_error(std::string(attr) + " must be a number (float), not " + type_name(v));
  }
  if (!(x > 0 && std::isfinite(x))) bad(std::string(attr) + " must be " + what + ", not " + py::repr(v).cast<std::string>());
  return x;
}

// A list of `attr`: any sequence but a str, bytes or a dict.
bool is_list(const py::handle& v) {
  return PySequence_Check(v.ptr()) && !py::isinstance<py::str>(v) && !py::isinstance<py::bytes>(v) &&
         !py::isinstance<py::dict>(v);
}

Category category(const std::string& name) {
  for (int c = 0; c < kCategories; ++c)
    if (name == category_name(Category(c))) return Category(c);
  std::string names;
  for (int c = 0; c < kCategories; ++c) names += std::string(c ? ", " : "") + category_name(Category(c));
  bad("unknown traffic category '" + name + "' (" + names + ")");
}

// What FrameSim cannot see of a job: that it has records, and incoming
// bytes within what a GPM's DRAM holds (its GPMs, framebuffers and units
// FrameSim::tiles_together checks).
void check_job(const PySim& s, const PyJob& j) {
  if (!j.token) bad("a TileJob without records");
  if (j.job.incoming > s.dram_bytes)
    bad(arg("TileJob", "incoming", std::to_string(j.job.incoming)) + "more than " + s.dram_holds());
}

// A scheme written in Python, run by the library like any other.
class PythonScheme final : public Scheme {
 public:
  explicit PythonScheme(py::object obj) : m_obj(std::move(obj)) {}
  ~PythonScheme() override {
    py::gil_scoped_acquire gil;
    m_obj = py::object();
  }

  int frames_needed(int gpms) const override {
    py::gil_scoped_acquire gil;
    if (!py::hasattr(m_obj, "frames_needed")) return 1;
    const py::object got = m_obj.attr("frames_needed")(gpms);
    const py::object i = as_int(got);
    if (!i)
      throw py::type_error("a scheme's frames_needed() must return the frames it renders at once (an int), not " +
                           type_name(got));
    int overflow = 0;
    const long long n = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow || n < 1 || n > 1024)
      bad("frames_needed() returned " + py::repr(i).cast<std::string>() + ": a scheme renders 1 to 1024 frames at once");
    return int(n);
  }

  // A scheme written in Python edits a configuration (a copy of the one
  // the machine was read from, its changes naming the scheme as their
  // source); the machine is then read again from it, once.
  void configure(MachineSpec& spec) const override {
    py::gil_scoped_acquire gil;
    if (!py::hasattr(m_obj, "configure")) return;
    Config config = spec.config;
    config.set_source(spec.source());
    py::object copy = py::cast(config);  // Python changes a copy; it is taken back whole
    m_obj.attr("configure")(copy);
    spec = MachineSpec::from_config(copy.cast<Config>());
  }

  SchemeResult run(const SchemeInput& in) const override {
    py::gil_scoped_acquire gil;
    auto token = std::make_shared<RunToken>();
    struct End {  // whatever run() does, what it was given dies with it
      Token t;
      ~End() { t->alive = false; }
    } end{token};
    auto input = std::make_shared<PyInput>(PyInput{token, in});
    py::object out = m_obj.attr("run")(input);
    if (!py::isinstance<PyResult>(out))
      throw py::type_error("a scheme's run() must return what FrameSim.finish() returned, not " +
                           std::string(py::str(py::type::of(out).attr("__name__"))));
    return out.cast<const PyResult&>().r;
  }

 private:
  py::object m_obj;
};

}  // namespace

SchemeRef scheme_of(const py::handle& s) {
  if (py::isinstance<py::str>(s)) return find_scheme(s.cast<std::string>());
  if (!py::hasattr(s, "run"))
    throw py::type_error("a scheme is a registered scheme's name (str) or an object with a run(input) method, not " +
                         type_name(s));
  if (!PyCallable_Check(s.attr("run").ptr()))
    throw py::type_error("a scheme's run is a method run(input), not " + type_name(s.attr("run")) + " (not callable)");
  // Its `name`, else its class's name.
  std::string name;
  if (py::hasattr(s, "name")) {
    const py::object n = s.attr("name");
    if (!py::isinstance<py::str>(n)) throw py::type_error("a scheme's name must be a str, not " + type_name(n));
    name = n.cast<std::string>();
  }
  if (name.empty()) name = py::str(py::type::of(s).attr("__name__")).cast<std::string>();
  // Results carry the name, and a registered scheme's name means that
  // scheme (the comparison's ratios are against "baseline"): a Python
  // scheme cannot take one.
  if (Schemes::find(name))
    throw Error("a Python scheme cannot be named '" + name + "': that is a registered scheme's name ('oovr schemes' lists " +
                "them); give it a name of its own");
  return {name, std::make_shared<PythonScheme>(py::reinterpret_borrow<py::object>(s))};
}

void bind_schemes(py::module_& m) {
  py::class_<PyRecord>(m, "Record",
                       "One (object, eye, screen tile) record of a frame's trace: the work of one object "
                       "for one eye in one 16x16 tile.")
      .def_property_readonly(
          "object", [](const PyRecord& r) { return r.get().object; }, "The object (draw) index.")
      .def_property_readonly(
          "eye", [](const PyRecord& r) { return r.get().eye; }, "0: left, 1: right.")
      .def_property_readonly(
          "tile_x", [](const PyRecord& r) { return r.get().tile_x; }, "Tile column in the stereo frame.")
      .def_property_readonly(
          "tile_y", [](const PyRecord& r) { return r.get().tile_y; }, "Tile row, from the frame's bottom.")
      .def_property_readonly(
          "triangles", [](const PyRecord& r) { return r.get().triangles; }, "Triangles binned to the tile.")
      .def_property_readonly(
          "covered", [](const PyRecord& r) { return r.get().covered; }, "Fragments covered.")
      .def_property_readonly(
          "shaded", [](const PyRecord& r) { return r.get().shaded; }, "Fragments shaded.")
      .def_property_readonly(
          "passed", [](const PyRecord& r) { return r.get().passed; }, "Fragments that passed the depth and alpha tests.")
      .def_property_readonly(
          "texture_lines", [](const PyRecord& r) { return r.get().tex_count; }, "Texture lines sampled.");

  py::class_<PyRecords>(m, "Records", "Tile records of one frame, in trace order: what a TileJob renders.")
      .def("__len__",
           [](const PyRecords& r) {
             check_alive(r.token, "a Records");
             return r.records.size();
           })
      .def(
          "__getitem__",
          [](const PyRecords& r, long i) {
            check_alive(r.token, "a Records");
            const long n = long(r.records.size());
            if (i < 0) i += n;
            if (i < 0 || i >= n) throw py::index_error("record " + std::to_string(i) + " of " + std::to_string(n));
            return PyRecord{r.token, r.records[size_t(i)]};
          },
          py::arg("index"))
      .def(
          "split",
          [](const PyRecords& r, const py::function& key, int64_t parts) {
            check_alive(r.token, "a Records");
            if (parts < 1 || parts > 4096) bad(arg("split", "parts", parts) + "parts must be 1 to 4096");
            std::vector<PyRecords> out(size_t(parts), PyRecords{r.token, r.trace, {}});
            for (const TileWork* w : r.records) {
              const int64_t k = returned_int(
                  key(PyRecord{r.token, w}), [] { return std::string("split(key): the key"); }, "a part (int)");
              if (k < 0 || k >= parts)
                bad("split(key): the key gave " + std::to_string(k) + ", not 0 to " + std::to_string(parts - 1) + " (parts " +
                    std::to_string(parts) + ")");
              out[size_t(k)].records.push_back(w);
            }
            return out;
          },
          py::arg("key").none(false), py::arg("parts"),
          "The records in `parts` groups by key(record) (0 to parts-1), each in trace order: e.g. by the GPM owning "
          "each record's tile.")
      .def(
          "__add__",
          [](const PyRecords& a, const PyRecords& b) {
            check_alive(a.token, "a Records");
            check_alive(b.token, "a Records");
            if (a.trace != b.trace) bad("records of two frames cannot be joined");
            PyRecords out = a;
            out.records.insert(out.records.end(), b.records.begin(), b.records.end());
            return out;
          },
          py::arg("other").none(false));

  py::class_<PyTrace>(m, "Trace", "One frame's FrameTrace, as a scheme sees it.")
      .def_property_readonly(
          "frame", [](const PyTrace& t) { return t.get().frame; }, "The frame of the camera path.")
      .def_property_readonly(
          "tiles_x", [](const PyTrace& t) { return t.get().tiles_x; }, "Tile columns of the stereo frame.")
      .def_property_readonly(
          "tiles_y", [](const PyTrace& t) { return t.get().tiles_y; }, "Tile rows.")
      .def_property_readonly(
          "objects", [](const PyTrace& t) { return t.get().objects.size(); }, "Objects (draws), in draw order.")
      .def(
          "triangles_set_up",
          [](const PyTrace& t, int64_t object, int64_t eye) {
            const FrameTrace& f = t.get();
            if (object < 0 || uint64_t(object) >= f.objects.size())
              bad(arg("triangles_set_up", "object", object) + "object " + std::to_string(object) +
                  " does not exist (objects 0 to " + std::to_string(int64_t(f.objects.size()) - 1) + ")");
            if (eye < 0 || eye > 1) bad(arg("triangles_set_up", "eye", eye) + "eye is 0 (left) or 1 (right)");
            return f.objects[size_t(object)].setup[eye];
          },
          py::arg("object"), py::arg("eye"), "Triangles of `object` set up for `eye` (after clip and cull).")
      .def(
          "records",
          [](const PyTrace& t) {
            const FrameTrace& f = t.get();
            PyRecords r{t.token, &f, {}};
            for (const TileWork& w : f.tiles) r.records.push_back(&w);
            return r;
          },
          "Every tile record of the frame, in trace order (draw, eye, tile).")
      .def(
          "records_by_object",
          [](const PyTrace& t) {
            const FrameTrace& f = t.get();
            std::vector<std::pair<PyRecords, PyRecords>> out;
            for (const ObjectRecords& o : records_by_object(f, f.objects.size()))
              out.push_back({PyRecords{t.token, &f, o.eye[0]}, PyRecords{t.token, &f, o.eye[1]}});
            return out;
          },
          "Per object, in draw order, its (left, right) records.");

  py::class_<PyInput, std::shared_ptr<PyInput>>(m, "SchemeInput", "What a scheme's run() is given: the frames to render.")
      .def_property_readonly(
          "frames",
          [](const PyInput& i) {
            check_alive(i.token, "a SchemeInput");
            return i.in.frames.size();
          },
          "Frames of trace (one unless the scheme renders several at once).")
      .def(
          "frame",
          [](const PyInput& i, int64_t k) {
            check_alive(i.token, "a SchemeInput");
            if (k < 0 || uint64_t(k) >= i.in.frames.size())
              bad(arg("frame", "k", k) + "frame " + std::to_string(k) + " does not exist (frames 0 to " +
                  std::to_string(int64_t(i.in.frames.size()) - 1) + ")");
            return PyTrace{i.token, i.in.frames[size_t(k)]};
          },
          py::arg("k") = 0, "The k-th frame's trace.")
      .def_property_readonly("objects", &PyInput::objects, "Objects of the scene.")
      .def_property_readonly(
          "gpms",
          [](const PyInput& i) {
            check_alive(i.token, "a SchemeInput");
            return i.in.spec->memory.gpms;
          },
          "GPMs of the configured machine (key gpms).")
      .def_property_readonly(
          "config",
          [](const PyInput& i) {
            check_alive(i.token, "a SchemeInput");
            return i.in.spec->config;
          },
          "The machine configuration (a copy).");

  py::class_<PySim, std::shared_ptr<PySim>>(m, "FrameSim",
                                            "A memory system and timing engine for the configured machine with the scene laid "
                                            "out in memory: the work a scheme adds is replayed through it (schemes/frame_sim.h).")
      .def(py::init([](const std::shared_ptr<PyInput>& i, int64_t framebuffers) {
             check_alive(i->token, "a SchemeInput");
             if (framebuffers < 1 || framebuffers > 1 + kMaxGpms)
               bad(arg("FrameSim", "framebuffers", framebuffers) + "framebuffers must be 1 to " + std::to_string(1 + kMaxGpms));
             auto s = std::make_shared<PySim>();
             s->token = i->token;
             s->sim = std::make_unique<FrameSim>(i->in, int(framebuffers));
             s->framebuffers = int(framebuffers);
             s->frames = i->in.frames;
             s->objects = most_draws(i->in);
             s->dram_bytes = i->in.spec->memory.dram_capacity.value;
             return s;
           }),
           py::arg("input").none(false), py::arg("framebuffers") = 1,
           "`framebuffers` colour and depth buffer pairs (sort_last_framebuffers(gpms) for sort-last schemes).")
      .def_property_readonly(
          "gpms", [](PySim& s) { return s.get().gpms(); }, "GPMs of the machine.")
      .def_property_readonly(
          "sms", [](PySim& s) { return s.get().sms(); }, "SMs per GPM.")
      .def(
          "frame",
          [](PySim& s, int64_t k) {
            (void)s.get();
            if (k < 0 || uint64_t(k) >= s.frames.size())
              bad(arg("frame", "k", k) + "frame " + std::to_string(k) + " does not exist (frames 0 to " +
                  std::to_string(int64_t(s.frames.size()) - 1) + ")");
            return PyTrace{s.token, s.frames[size_t(k)]};
          },
          py::arg("k") = 0, "The k-th frame's trace.")
      .def(
          "command",
          [](PySim& s, int64_t gpm, const py::object& draws) {
            FrameSim& f = s.adding();
            const int g = PySim::index(gpm, "command", "gpm");
            const uint64_t most = s.bounds().draws;
            const uint64_t n = count(draws, "command", "draws", most, [&] {
              return "this run's frames hold (" + std::to_string(most) + ": both views of " + std::to_string(s.objects) +
                     " objects in " + std::to_string(s.frames.size()) + " frames)";
            });
            return f.command(g, int(n));
          },
          py::arg("gpm"), py::arg("draws") = 1,
          "GPM `gpm`'s front end receives `draws` draws (per-draw cost); the draw becomes the GPM's current one. Returns "
          "the unit.")
      .def(
          "use_draw",
          [](PySim& s, int64_t gpm, int64_t unit) {
            FrameSim& f = s.adding();
            f.use_draw(PySim::index(gpm, "use_draw", "gpm"), PySim::index(unit, "use_draw", "command_unit"));
          },
          py::arg("gpm"), py::arg("command_unit"), "Pipeline units added on `gpm` from now on belong to that draw.")
      .def(
          "geometry",
          [](PySim& s, int64_t gpm, int64_t object, int64_t vertex_passes, const py::object& triangles,
             const std::vector<int64_t>& after) {
            FrameSim& f = s.adding();
            const int g = PySim::index(gpm, "geometry", "gpm");
            const uint32_t o = s.object(object, "geometry");
            const uint64_t t = triangles_of(s, o, triangles, "geometry");
            return f.geometry(g, o, PySim::index(vertex_passes, "geometry", "vertex_passes"), t, PySim::units(after, "geometry"));
          },
          py::arg("gpm"), py::arg("object"), py::arg("vertex_passes"), py::arg("triangles"),
          py::arg("after") = std::vector<int>{},
          "Vertex shading and set-up of `object` on `gpm` (vertex_passes 1 with SMP, 2 without); returns the unit.")
      .def(
          "geometry_part",
          [](PySim& s, int64_t gpm, int64_t object, double begin, double end, double vertex_cost, const py::object& triangles,
             const std::vector<int64_t>& after) {
            FrameSim& f = s.adding();
            const int g = PySim::index(gpm, "geometry_part", "gpm");
            const uint32_t o = s.object(object, "geometry_part");
            const uint64_t t = triangles_of(s, o, triangles, "geometry_part");
            return f.geometry_part(g, o, begin, end, vertex_cost, t, PySim::units(after, "geometry_part"));
          },
          py::arg("gpm"), py::arg("object"), py::arg("begin"), py::arg("end"), py::arg("vertex_cost"), py::arg("triangles"),
          py::arg("after") = std::vector<int>{},
          "A share [begin, end) of `object`'s vertices shaded on `gpm` at `vertex_cost` of the vertex shader (GPUpd's "
          "projection), `triangles` set up; returns the unit.")
      .def(
          "tiles",
          [](PySim& s, int64_t gpm, const PyRecords& records, int64_t fb, const std::vector<int64_t>& after, int64_t from_gpm,
             const py::object& incoming) {
            FrameSim& f = s.adding();
            const FrameTrace* t = s.own(records, "tiles");
            const int g = PySim::index(gpm, "tiles", "gpm");
            const int b = PySim::index(fb, "tiles", "fb");
            std::vector<int> units = PySim::units(after, "tiles");
            const int from = PySim::index(from_gpm, "tiles", "from_gpm");
            const uint64_t bytes = s.bytes(incoming, "tiles", "incoming");
            return f.tiles(g, records.records, b, *t, std::move(units), from, bytes);
          },
          py::arg("gpm"), py::arg("records").none(false), py::arg("fb") = 0, py::arg("after") = std::vector<int>{},
          py::arg("from_gpm") = -1, py::arg("incoming") = 0,
          "Rasterisation, shading, texturing and ROP work of `records` on `gpm`, into framebuffer `fb`; `incoming` bytes "
          "of set-up triangles come from `from_gpm` first. Returns the unit.")
      .def(
          "tiles_together",
          [](PySim& s, const std::vector<PyJob*>& jobs) {
            FrameSim& f = s.adding();
            if (jobs.empty()) bad("tiles_together(jobs=[]): no jobs");
            std::vector<FrameSim::TileJob> js;
            const FrameTrace* t = nullptr;
            for (const PyJob* j : jobs) {
              if (!j) throw py::type_error("tiles_together(jobs): a job is None, not a TileJob");
              check_job(s, *j);
              if (j->token != s.token) throw std::runtime_error("tiles_together: a job's records belong to another run");
              if (t && j->trace != t) bad("tiles_together: the jobs' records are of different frames");
              t = j->trace;
              js.push_back(j->job);
            }
            return f.tiles_together(js, *t);
          },
          py::arg("jobs"),
          "Several GPMs' tile work on one draw, replayed record by record in turn across the jobs; returns their units "
          "in job order.")
      .def(
          "transfer",
          [](PySim& s, int64_t from_gpm, int64_t to_gpm, const py::object& bytes, const std::string& what,
             const std::vector<int64_t>& after) {
            FrameSim& f = s.adding();
            const int from = PySim::index(from_gpm, "transfer", "from_gpm");
            const int to = PySim::index(to_gpm, "transfer", "to_gpm");
            const uint64_t n = s.bytes(bytes, "transfer", "bytes");
            const Category c = category(what);
            return f.transfer(from, to, n, c, PySim::units(after, "transfer"));
          },
          py::arg("from_gpm"), py::arg("to_gpm"), py::arg("bytes"), py::arg("category"), py::arg("after") = std::vector<int>{},
          "Moves bytes between GPMs over the links (category: vertex, index, texture, depth, colour, composition, "
          "prealloc, command); returns the unit.")
      .def(
          "compose",
          [](PySim& s, int64_t gpm, const py::object& pixels, const std::vector<int64_t>& after,
             const std::optional<PyRecords>& records) {
            FrameSim& f = s.adding();
            const int g = PySim::index(gpm, "compose", "gpm");
            const uint64_t most = s.bounds().pixels;
            const uint64_t n = count(pixels, "compose", "pixels", most, [&] {
              return "this run's frames can compose (at most " + std::to_string(most) +
                     ": per record, its passed fragments or its tile's pixels, the more)";
            });
            std::vector<int> units = PySim::units(after, "compose");
            std::vector<const TileWork*> merged;
            if (records) {
              (void)s.own(*records, "compose");
              merged = records->records;
            }
            return f.compose(g, merged, n, std::move(units));
          },
          py::arg("gpm"), py::arg("pixels"), py::arg("after") = std::vector<int>{}, py::arg("records") = py::none(),
          "ROP work merging `pixels` on `gpm` (composition), beside its pipeline: the pixels that `records` wrote into "
          "private buffers reach the final frame (the run's check counts each record's pixels composed once). Returns "
          "the unit.")
      .def(
          "declare_repeats",
          [](PySim& s, int64_t times) {
            FrameSim& f = s.adding();
            f.declare_repeats(PySim::index(times, "declare_repeats", "times"));
          },
          py::arg("times"), "The scheme rasterises some records up to `times` times by design (the run's check allows it).")
      .def(
          "end_draw",
          [](PySim& s, int64_t gpm) {
            FrameSim& f = s.adding();
            f.end_draw(PySim::index(gpm, "end_draw", "gpm"));
          },
          py::arg("gpm") = -1, "GPM `gpm` (-1: every GPM) finished a draw: call it after adding the draw's units there.")
      .def(
          "now", [](PySim& s) { return s.get().engine().now(); }, "From on_finish: the simulated time, in seconds.")
      .def(
          "work_left",
          [](PySim& s, int64_t unit) {
            (void)s.get();
            return s.sim->engine().work_left(s.unit(unit, "work_left"));
          },
          py::arg("unit"), "From on_finish: the fraction of a unit's work still to do.")
      .def(
          "finish",
          [](PySim& s, const std::string& name, int64_t frames_in_flight,
             const std::optional<std::function<void(int)>>& on_finish) {
            FrameSim& f = s.get();
            if (s.state != PySim::State::building)
              throw std::runtime_error("FrameSim.finish() runs once (it has run, or it is running: on_finish adds work)");
            if (frames_in_flight < 1 || uint64_t(frames_in_flight) >= s.frames.size() + 1)
              bad(arg("finish", "frames_in_flight", frames_in_flight) + "frames_in_flight must be 1 to the frames given (" +
                  std::to_string(s.frames.size()) + ")");
            std::function<void(int)> hook;
            if (on_finish) hook = *on_finish;
            s.state = PySim::State::running;
            struct Done {  // however the engine's run ends
              PySim& s;
              ~Done() { s.state = PySim::State::done; }
            } done{s};
            return PyResult{f.finish(name, int(frames_in_flight), hook)};
          },
          py::arg("name"), py::arg("frames_in_flight") = 1, py::arg("on_finish") = py::none(),
          "Runs the timing engine over the work added; `on_finish(unit)` is called as units end and may add work. "
          "Returns the result run() returns.");

  py::class_<PyJob>(m, "TileJob", "One GPM's share of a draw's tile work (FrameSim.tiles_together).")
      .def(py::init([](int64_t gpm, const PyRecords& records, int64_t fb, const std::vector<int64_t>& after, int64_t from_gpm,
                       const py::object& incoming) {
             check_alive(records.token, "a Records");
             // Checked against the machine where the job is used (check_job);
             // here, what no machine has.
             if (gpm < 0 || gpm >= kMaxGpms)
               bad(arg("TileJob", "gpm", gpm) + "GPM " + std::to_string(gpm) + " does not exist (a machine has at most " +
                   std::to_string(kMaxGpms) + " GPMs)");
             if (fb < 0 || fb > kMaxGpms)
               bad(arg("TileJob", "fb", fb) + "framebuffer " + std::to_string(fb) + " does not exist (at most " +
                   std::to_string(1 + kMaxGpms) + ")");
             if (from_gpm < -1 || from_gpm >= kMaxGpms)
               bad(arg("TileJob", "from_gpm", from_gpm) + "GPM " + std::to_string(from_gpm) + " does not exist (-1 for none)");
             std::vector<int> units;
             for (int64_t u : after) {
               if (u < -1 || u > INT_MAX) bad("TileJob(after): unit " + std::to_string(u) + " has not been added (-1 for none)");
               units.push_back(int(u));
             }
             const uint64_t bytes =
                 count(incoming, "TileJob", "incoming", UINT64_MAX, [] { return std::string("any size oovr takes"); });
             PyJob j;
             j.token = records.token;
             j.trace = records.trace;
             j.job = FrameSim::TileJob{int(gpm), records.records, int(fb), std::move(units), int(from_gpm), bytes};
             return j;
           }),
           py::arg("gpm"), py::arg("records").none(false), py::arg("fb") = 0, py::arg("after") = std::vector<int>{},
           py::arg("from_gpm") = -1, py::arg("incoming") = 0)
      .def_property_readonly(
          "gpm", [](const PyJob& j) { return j.job.gpm; }, "The GPM doing the work.")
      .def_property_readonly(
          "records", [](const PyJob& j) { return j.job.records.size(); }, "How many records.");

  py::class_<PyComposer>(m, "Composer",
                         "Sort-last composition (schemes/composition.h): every pixel of the final frame has an owner GPM; a "
                         "GPM writes the pixels it owns into the final frame and sends the others to their owners.")
      .def(py::init([](const std::shared_ptr<PySim>& sim, const py::object& owner) {
             FrameSim& f = sim->get();
             std::function<int(int, int)> fn;
             const int gpms = f.gpms();
             if (as_int(owner)) {
               const int64_t root = whole(owner, "Composer(owner)");
               if (root < 0 || root >= gpms)
                 bad(arg("Composer", "owner", root) + "GPM " + std::to_string(root) + " does not exist (GPMs 0 to " +
                     std::to_string(gpms - 1) + ")");
               fn = [root](int, int) { return int(root); };
             } else if (PyCallable_Check(owner.ptr())) {
               // Checked on every call: the owner is the scheme's code.
               fn = [owner, gpms](int x, int y) {
                 return returned_gpm(owner(x, y), gpms, [&] {
                   return "Composer(owner): owner(" + std::to_string(x) + ", " + std::to_string(y) + ")";
                 });
               };
             } else {
               throw py::type_error("Composer(owner): the owner is a GPM (int) or a function (tile_x, tile_y) -> GPM, not " +
                                    type_name(owner));
             }
             return PyComposer{sim, std::make_unique<Composer>(f, f.spec().composition, fn)};
           }),
           py::arg("sim").none(false), py::arg("owner"),
           "`owner`: the GPM owning every pixel (the root), or a function (tile_x, tile_y) -> GPM. The payload and "
           "granularity come from the configuration (composition.payload, composition.granularity).")
      .def(
          "target",
          [](PyComposer& c, PyJob& j) {
            Composer& comp = c.get();
            check_job(*c.sim, j);
            comp.target(j.job);
          },
          py::arg("job").none(false),
          "Sets where the job's records write: owned pixels into the final frame, the rest into its own buffer.")
      .def(
          "send",
          [](PyComposer& c, const PyJob& j, int64_t unit) {
            Composer& comp = c.get();
            check_job(*c.sim, j);
            comp.send(j.job, c.sim->unit(unit, "send"));
          },
          py::arg("job").none(false), py::arg("unit"),
          "After `unit` (the job's work), sends the job's pixels owned elsewhere to their owners, whose ROPs merge them.");

  // A scheme may restate what a frame's latency is after finish(), as AFR
  // does (its frames' latencies are their GPMs' busy times).
  py::class_<PyResult>(m, "SchemeResult",
                       "What FrameSim.finish() returns and a scheme's run() hands back; a scheme may set its latencies, "
                       "throughput and notes before returning it.")
      .def_property_readonly(
          "scheme", [](const PyResult& r) { return r.r.scheme; }, "The name given to finish().")
      .def_property_readonly(
          "gpms", [](const PyResult& r) { return r.r.gpms; }, "GPMs of the machine.")
      .def_property(
          "frame_latency_s", [](const PyResult& r) { return r.r.frame_latency_s; },
          [](PyResult& r, const py::object& v) {
            r.r.frame_latency_s = positive(v, "frame_latency_s", "a positive number of seconds");
          },
          "One frame, first command to last pixel, seconds.")
      .def_property(
          "frame_latencies_s", [](const PyResult& r) { return r.r.frame_latencies_s; },
          [](PyResult& r, const py::object& v) {
            if (!is_list(v)) throw py::type_error("frame_latencies_s must be a list of seconds (floats), not " + type_name(v));
            std::vector<double> seconds;
            for (const py::handle& x : v) seconds.push_back(positive(x, "frame_latencies_s", "positive numbers of seconds"));
            if (seconds.empty()) bad("frame_latencies_s needs at least one frame");
            r.r.frame_latencies_s = std::move(seconds);
          },
          "Each frame's latency (several with frames in flight).")
      .def_property(
          "throughput_fps", [](const PyResult& r) { return r.r.throughput_fps; },
          [](PyResult& r, const py::object& v) { r.r.throughput_fps = positive(v, "throughput_fps", "a positive number"); },
          "Frames per second, frames in flight overlapping.")
      .def_property(
          "notes", [](const PyResult& r) { return r.r.notes; },
          [](PyResult& r, const py::object& v) {
            if (!is_list(v)) throw py::type_error("notes must be a list of str, not " + type_name(v));
            std::vector<std::string> notes;
            for (const py::handle& n : v) {
              if (!py::isinstance<py::str>(n)) throw py::type_error("notes must be a list of str, not of " + type_name(n));
              notes.push_back(n.cast<std::string>());
            }
            r.r.notes = std::move(notes);
          },
          "What the scheme reports of itself, as text.")
      .def_property_readonly(
          "gpm_busy_s", [](const PyResult& r) { return r.r.gpm_busy_s; }, "Each GPM's busy time, seconds.")
      .def_property_readonly(
          "inter_gpm_bytes", [](const PyResult& r) { return r.r.total_inter_gpm_bytes(); }, "Bytes moved between GPMs.");

  m.def(
      "sort_last_framebuffers",
      [](int64_t gpms) {
        if (gpms < 1 || gpms > kMaxGpms)
          bad(arg("sort_last_framebuffers", "gpms", gpms) + "a machine has 1 to " + std::to_string(kMaxGpms) + " GPMs");
        return sort_last_framebuffers(int(gpms));
      },
      py::arg("gpms"), "Framebuffers of a sort-last scheme: 0 is the final frame, 1 + g GPM g's own.");
  m.def(
      "vertical_strip_owner",
      [](int64_t tile_x, int64_t tiles_x, int64_t gpms) {
        // A frame is at most 16384 pixels wide (resolutions are checked so).
        constexpr int64_t most_tiles = 16384;
        if (gpms < 1 || gpms > kMaxGpms)
          bad(arg("vertical_strip_owner", "gpms", gpms) + "a machine has 1 to " + std::to_string(kMaxGpms) + " GPMs");
        if (tiles_x < 1 || tiles_x > most_tiles)
          bad(arg("vertical_strip_owner", "tiles_x", tiles_x) + "a frame has 1 to " + std::to_string(most_tiles) +
              " tile columns");
        if (tile_x < 0 || tile_x >= tiles_x)
          bad(arg("vertical_strip_owner", "tile_x", tile_x) + "tile columns are 0 to " + std::to_string(tiles_x - 1));
        return vertical_strip_owner(int(tile_x), int(tiles_x), int(gpms));
      },
      py::arg("tile_x"), py::arg("tiles_x"), py::arg("gpms"),
      "The GPM owning tile column `tile_x` when the frame is cut into one vertical strip of whole tile columns per GPM.");
  m.def(
      "sort_first",
      [](const std::shared_ptr<PySim>& s, const py::function& owner, const std::string& geometry) {
        FrameSim& f = s->adding();
        Geometry g;
        if (geometry == "shared") g = Geometry::shared;
        else if (geometry == "duplicated_smp") g = Geometry::duplicated_smp;
        else if (geometry == "duplicated_per_eye") g = Geometry::duplicated_per_eye;
        else bad("sort_first: geometry is shared, duplicated_smp or duplicated_per_eye, not '" + geometry + "'");
        const int gpms = f.gpms();
        sort_first(
            f,
            [&](int x, int y, int eye) {
              return returned_gpm(owner(x, y, eye), gpms, [&] {
                return "sort_first(owner): owner(" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(eye) +
                       ")";
              });
            },
            g);
      },
      py::arg("sim").none(false), py::arg("owner").none(false), py::arg("geometry"),
      "Renders frame 0 sort-first, draw by draw, every tile by its owner(tile_x, tile_y, eye); geometry 'shared' "
      "(once per draw, SMP), 'duplicated_smp' or 'duplicated_per_eye' (schemes/sort_first.h).");
}

}  // namespace oovr::python
