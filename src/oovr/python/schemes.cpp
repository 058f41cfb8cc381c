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
// traces. Arguments are checked (GPMs, objects, framebuffers, units) before
// they reach the C++, so a mistake is a ValueError, never a crash.
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <cmath>

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

struct PyInput {
  Token token;
  SchemeInput in;
  size_t objects() const {
    check_alive(token, "a SchemeInput");
    return in.scene->objects.size();
  }
};

struct PySim {
  Token token;
  std::unique_ptr<FrameSim> sim;
  int framebuffers = 1;
  std::vector<const FrameTrace*> frames;
  size_t objects = 0;
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
  void gpm(int g, const char* what) const {
    if (g < 0 || g >= sim->gpms())
      bad(std::string(what) + ": GPM " + std::to_string(g) + " does not exist (GPMs 0 to " + std::to_string(sim->gpms() - 1) +
          ")");
  }
  void fb(int f, const char* what) const {
    if (f < 0 || f >= framebuffers)
      bad(std::string(what) + ": framebuffer " + std::to_string(f) + " does not exist (this FrameSim has " +
          std::to_string(framebuffers) + ")");
  }
  void units(const std::vector<int>& after, const char* what) const {
    const int n = int(sim->engine().units());
    for (int u : after)
      if (u < -1 || u >= n)
        bad(std::string(what) + ": unit " + std::to_string(u) + " has not been added (units 0 to " + std::to_string(n - 1) +
            "; -1 for none)");
  }
  const FrameTrace* own(const PyRecords& r, const char* what) const {
    check_alive(r.token, "a Records");
    if (r.token != token) throw std::runtime_error(std::string(what) + ": the records belong to another run");
    if (std::find(frames.begin(), frames.end(), r.trace) == frames.end())
      bad(std::string(what) + ": the records are not of this run's frames");
    return r.trace;
  }
};

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

Category category(const std::string& name) {
  for (int c = 0; c < kCategories; ++c)
    if (name == category_name(Category(c))) return Category(c);
  std::string names;
  for (int c = 0; c < kCategories; ++c) names += std::string(c ? ", " : "") + category_name(Category(c));
  bad("unknown traffic category '" + name + "' (" + names + ")");
}

void check_job(const PySim& s, const PyJob& j) {
  if (!j.token) bad("a TileJob without records");
  s.gpm(j.job.gpm, "TileJob");
  s.fb(j.job.fb, "TileJob");
  s.units(j.job.after, "TileJob.after");
  if (j.job.from >= s.sim->gpms() || j.job.from < -1) bad("TileJob.from_gpm " + std::to_string(j.job.from) + " does not exist");
  for (const auto* v : {&j.job.fbs, &j.job.depth_fbs}) {
    if (!v->empty() && v->size() != j.job.records.size())
      bad("TileJob: per-record framebuffers must be one per record (" + std::to_string(j.job.records.size()) + "), not " +
          std::to_string(v->size()));
    for (int f : *v) s.fb(f, "TileJob");
  }
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
    const int n = m_obj.attr("frames_needed")(gpms).cast<int>();
    if (n < 1 || n > 1024) bad("frames_needed() returned " + std::to_string(n) + ": a scheme renders 1 to 1024 frames at once");
    return n;
  }

  void configure(Config& config) const override {
    py::gil_scoped_acquire gil;
    if (!py::hasattr(m_obj, "configure")) return;
    py::object copy = py::cast(config);  // Python changes a copy; it is taken back whole
    m_obj.attr("configure")(copy);
    config = copy.cast<Config>();
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
                         std::string(py::str(py::type::of(s).attr("__name__"))));
  // Its `name`, else its class's name.
  std::string name = py::hasattr(s, "name") ? py::str(s.attr("name")).cast<std::string>() : "";
  if (name.empty()) name = py::str(py::type::of(s).attr("__name__")).cast<std::string>();
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
          [](const PyRecords& r, const std::function<int(const PyRecord&)>& key, int parts) {
            check_alive(r.token, "a Records");
            if (parts < 1 || parts > 4096) bad("split: parts must be 1 to 4096");
            std::vector<PyRecords> out(size_t(parts), PyRecords{r.token, r.trace, {}});
            for (const TileWork* w : r.records) {
              const int k = key(PyRecord{r.token, w});
              if (k < 0 || k >= parts)
                bad("split: the key gave " + std::to_string(k) + ", not 0 to " + std::to_string(parts - 1));
              out[size_t(k)].records.push_back(w);
            }
            return out;
          },
          py::arg("key"), py::arg("parts"),
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
          py::arg("other"));

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
          [](const PyTrace& t, uint32_t object, int eye) {
            const FrameTrace& f = t.get();
            if (object >= f.objects.size()) bad("object " + std::to_string(object) + " does not exist");
            if (eye < 0 || eye > 1) bad("eye " + std::to_string(eye) + ": 0 (left) or 1 (right)");
            return f.objects[object].setup[eye];
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
          [](const PyInput& i, size_t k) {
            check_alive(i.token, "a SchemeInput");
            if (k >= i.in.frames.size())
              throw py::index_error("frame " + std::to_string(k) + " of " + std::to_string(i.in.frames.size()));
            return PyTrace{i.token, i.in.frames[k]};
          },
          py::arg("k") = 0, "The k-th frame's trace.")
      .def_property_readonly("objects", &PyInput::objects, "Objects of the scene.")
      .def_property_readonly(
          "gpms",
          [](const PyInput& i) {
            check_alive(i.token, "a SchemeInput");
            Config probe = i.in.config;
            return MemorySpec::from_config(probe).gpms;
          },
          "GPMs of the configured machine (key gpms).")
      .def_property_readonly(
          "config",
          [](const PyInput& i) {
            check_alive(i.token, "a SchemeInput");
            return i.in.config;
          },
          "The machine configuration (a copy).");

  py::class_<PySim, std::shared_ptr<PySim>>(m, "FrameSim",
                                            "A memory system and timing engine for the configured machine with the scene laid "
                                            "out in memory: the work a scheme adds is replayed through it (schemes/frame_sim.h).")
      .def(py::init([](const std::shared_ptr<PyInput>& i, int framebuffers) {
             check_alive(i->token, "a SchemeInput");
             if (framebuffers < 1 || framebuffers > 1 + kMaxGpms)
               bad("framebuffers must be 1 to " + std::to_string(1 + kMaxGpms));
             auto s = std::make_shared<PySim>();
             s->token = i->token;
             s->sim = std::make_unique<FrameSim>(i->in, framebuffers);
             s->framebuffers = framebuffers;
             s->frames = i->in.frames;
             s->objects = i->in.scene->objects.size();
             return s;
           }),
           py::arg("input"), py::arg("framebuffers") = 1,
           "`framebuffers` colour and depth buffer pairs (sort_last_framebuffers(gpms) for sort-last schemes).")
      .def_property_readonly(
          "gpms", [](PySim& s) { return s.get().gpms(); }, "GPMs of the machine.")
      .def_property_readonly(
          "sms", [](PySim& s) { return s.get().sms(); }, "SMs per GPM.")
      .def(
          "frame",
          [](PySim& s, size_t k) {
            (void)s.get();
            if (k >= s.frames.size())
              throw py::index_error("frame " + std::to_string(k) + " of " + std::to_string(s.frames.size()));
            return PyTrace{s.token, s.frames[k]};
          },
          py::arg("k") = 0, "The k-th frame's trace.")
      .def(
          "command",
          [](PySim& s, int gpm, int draws) {
            FrameSim& f = s.adding();
            s.gpm(gpm, "command");
            if (draws < 1) bad("command: draws must be at least 1");
            return f.command(gpm, draws);
          },
          py::arg("gpm"), py::arg("draws") = 1,
          "GPM `gpm`'s front end receives `draws` draws (per-draw cost); the draw becomes the GPM's current one. Returns "
          "the unit.")
      .def(
          "use_draw",
          [](PySim& s, int gpm, int unit) {
            FrameSim& f = s.adding();
            s.gpm(gpm, "use_draw");
            s.units({unit}, "use_draw");
            f.use_draw(gpm, unit);
          },
          py::arg("gpm"), py::arg("command_unit"), "Pipeline units added on `gpm` from now on belong to that draw.")
      .def(
          "geometry",
          [](PySim& s, int gpm, uint32_t object, int vertex_passes, uint64_t triangles, const std::vector<int>& after) {
            FrameSim& f = s.adding();
            s.gpm(gpm, "geometry");
            if (object >= s.objects) bad("geometry: object " + std::to_string(object) + " does not exist");
            if (vertex_passes < 1 || vertex_passes > 2) bad("geometry: vertex_passes is 1 (SMP) or 2 (one per eye)");
            s.units(after, "geometry");
            return f.geometry(gpm, object, vertex_passes, triangles, after);
          },
          py::arg("gpm"), py::arg("object"), py::arg("vertex_passes"), py::arg("triangles"),
          py::arg("after") = std::vector<int>{},
          "Vertex shading and set-up of `object` on `gpm` (vertex_passes 1 with SMP, 2 without); returns the unit.")
      .def(
          "tiles",
          [](PySim& s, int gpm, const PyRecords& records, int fb, const std::vector<int>& after, int from_gpm,
             uint64_t incoming) {
            FrameSim& f = s.adding();
            const FrameTrace* t = s.own(records, "tiles");
            s.gpm(gpm, "tiles");
            s.fb(fb, "tiles");
            s.units(after, "tiles");
            if (from_gpm < -1 || from_gpm >= f.gpms()) bad("tiles: from_gpm " + std::to_string(from_gpm) + " does not exist");
            return f.tiles(gpm, records.records, fb, *t, after, from_gpm, incoming);
          },
          py::arg("gpm"), py::arg("records"), py::arg("fb") = 0, py::arg("after") = std::vector<int>{}, py::arg("from_gpm") = -1,
          py::arg("incoming") = 0,
          "Rasterisation, shading, texturing and ROP work of `records` on `gpm`, into framebuffer `fb`; `incoming` bytes "
          "of set-up triangles come from `from_gpm` first. Returns the unit.")
      .def(
          "tiles_together",
          [](PySim& s, const std::vector<PyJob*>& jobs) {
            FrameSim& f = s.adding();
            if (jobs.empty()) bad("tiles_together: no jobs");
            std::vector<FrameSim::TileJob> js;
            const FrameTrace* t = nullptr;
            for (const PyJob* j : jobs) {
              if (!j) bad("tiles_together: a job is None");
              check_job(s, *j);
              if (j->token != s.token) throw std::runtime_error("tiles_together: a job's records belong to another run");
              if (t && j->trace != t) bad("tiles_together: the jobs' records are of different frames");
              t = j->trace;
              js.push_back(j->job);
            }
            if (std::find(s.frames.begin(), s.frames.end(), t) == s.frames.end())
              bad("tiles_together: the records are not of this run's frames");
            return f.tiles_together(js, *t);
          },
          py::arg("jobs"),
          "Several GPMs' tile work on one draw, replayed record by record in turn across the jobs; returns their units "
          "in job order.")
      .def(
          "transfer",
          [](PySim& s, int from_gpm, int to_gpm, uint64_t bytes, const std::string& what, const std::vector<int>& after) {
            FrameSim& f = s.adding();
            s.gpm(from_gpm, "transfer");
            s.gpm(to_gpm, "transfer");
            s.units(after, "transfer");
            return f.transfer(from_gpm, to_gpm, bytes, category(what), after);
          },
          py::arg("from_gpm"), py::arg("to_gpm"), py::arg("bytes"), py::arg("category"), py::arg("after") = std::vector<int>{},
          "Moves bytes between GPMs over the links (category: vertex, index, texture, depth, colour, composition, "
          "prealloc, command); returns the unit.")
      .def(
          "compose",
          [](PySim& s, int gpm, uint64_t pixels, const std::vector<int>& after, const std::optional<PyRecords>& records) {
            FrameSim& f = s.adding();
            s.gpm(gpm, "compose");
            s.units(after, "compose");
            std::vector<const TileWork*> merged;
            if (records) {
              (void)s.own(*records, "compose");
              merged = records->records;
            }
            return f.compose(gpm, merged, pixels, after);
          },
          py::arg("gpm"), py::arg("pixels"), py::arg("after") = std::vector<int>{}, py::arg("records") = py::none(),
          "ROP work merging `pixels` on `gpm` (composition), beside its pipeline: the pixels that `records` wrote into "
          "private buffers reach the final frame (the run's check counts each record's pixels composed once). Returns "
          "the unit.")
      .def(
          "declare_repeats",
          [](PySim& s, int times) {
            FrameSim& f = s.adding();
            if (times < 1 || times > 1000) bad("declare_repeats: times must be 1 to 1000");
            f.declare_repeats(times);
          },
          py::arg("times"), "The scheme rasterises some records up to `times` times by design (the run's check allows it).")
      .def(
          "end_draw",
          [](PySim& s, int gpm) {
            FrameSim& f = s.adding();
            if (gpm != -1) s.gpm(gpm, "end_draw");
            f.end_draw(gpm);
          },
          py::arg("gpm") = -1, "GPM `gpm` (-1: every GPM) finished a draw: call it after adding the draw's units there.")
      .def(
          "now", [](PySim& s) { return s.get().engine().now(); }, "From on_finish: the simulated time, in seconds.")
      .def(
          "work_left",
          [](PySim& s, int unit) {
            (void)s.get();
            s.units({unit}, "work_left");
            if (unit < 0) bad("work_left: unit -1");
            return s.sim->engine().work_left(unit);
          },
          py::arg("unit"), "From on_finish: the fraction of a unit's work still to do.")
      .def(
          "finish",
          [](PySim& s, const std::string& name, int frames_in_flight, const std::optional<std::function<void(int)>>& on_finish) {
            FrameSim& f = s.get();
            if (s.state != PySim::State::building)
              throw std::runtime_error("FrameSim.finish() runs once (it has run, or it is running: on_finish adds work)");
            if (frames_in_flight < 1 || frames_in_flight > int(s.frames.size()))
              bad("finish: frames_in_flight must be 1 to the frames given (" + std::to_string(s.frames.size()) + ")");
            std::function<void(int)> hook;
            if (on_finish) hook = *on_finish;
            s.state = PySim::State::running;
            struct Done {  // however the engine's run ends
              PySim& s;
              ~Done() { s.state = PySim::State::done; }
            } done{s};
            return PyResult{f.finish(name, frames_in_flight, hook)};
          },
          py::arg("name"), py::arg("frames_in_flight") = 1, py::arg("on_finish") = py::none(),
          "Runs the timing engine over the work added; `on_finish(unit)` is called as units end and may add work. "
          "Returns the result run() returns.");

  py::class_<PyJob>(m, "TileJob", "One GPM's share of a draw's tile work (FrameSim.tiles_together).")
      .def(
          py::init([](int gpm, const PyRecords& records, int fb, const std::vector<int>& after, int from_gpm, uint64_t incoming) {
            check_alive(records.token, "a Records");
            PyJob j;
            j.token = records.token;
            j.trace = records.trace;
            j.job = FrameSim::TileJob{gpm, records.records, fb, after, from_gpm, incoming};
            return j;
          }),
          py::arg("gpm"), py::arg("records"), py::arg("fb") = 0, py::arg("after") = std::vector<int>{}, py::arg("from_gpm") = -1,
          py::arg("incoming") = 0)
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
             if (py::isinstance<py::int_>(owner)) {
               const int root = owner.cast<int>();
               sim->gpm(root, "Composer");
               fn = [root](int, int) { return root; };
             } else if (PyCallable_Check(owner.ptr())) {
               // Checked on every call: the owner is the scheme's code.
               fn = [owner, gpms](int x, int y) {
                 const int g = owner(x, y).cast<int>();
                 if (g < 0 || g >= gpms) bad("the composer's owner gave GPM " + std::to_string(g) + ", which does not exist");
                 return g;
               };
             } else {
               throw py::type_error("Composer's owner is a GPM (int) or a function (tile_x, tile_y) -> GPM");
             }
             return PyComposer{sim, std::make_unique<Composer>(f, CompositionSpec::from_config(f.config()), fn)};
           }),
           py::arg("sim"), py::arg("owner"),
           "`owner`: the GPM owning every pixel (the root), or a function (tile_x, tile_y) -> GPM. The payload and "
           "granularity come from the configuration (composition.payload, composition.granularity).")
      .def(
          "target",
          [](PyComposer& c, PyJob& j) {
            Composer& comp = c.get();
            check_job(*c.sim, j);
            comp.target(j.job);
          },
          py::arg("job"), "Sets where the job's records write: owned pixels into the final frame, the rest into its own buffer.")
      .def(
          "send",
          [](PyComposer& c, const PyJob& j, int unit) {
            Composer& comp = c.get();
            check_job(*c.sim, j);
            c.sim->units({unit}, "send");
            comp.send(j.job, unit);
          },
          py::arg("job"), py::arg("unit"),
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
          [](PyResult& r, double v) {
            if (!(v > 0 && std::isfinite(v))) bad("frame_latency_s must be a positive number of seconds");
            r.r.frame_latency_s = v;
          },
          "One frame, first command to last pixel, seconds.")
      .def_property(
          "frame_latencies_s", [](const PyResult& r) { return r.r.frame_latencies_s; },
          [](PyResult& r, const std::vector<double>& v) {
            if (v.empty()) bad("frame_latencies_s needs at least one frame");
            for (double x : v)
              if (!(x > 0 && std::isfinite(x))) bad("frame_latencies_s must be positive numbers of seconds");
            r.r.frame_latencies_s = v;
          },
          "Each frame's latency (several with frames in flight).")
      .def_property(
          "throughput_fps", [](const PyResult& r) { return r.r.throughput_fps; },
          [](PyResult& r, double v) {
            if (!(v > 0 && std::isfinite(v))) bad("throughput_fps must be a positive number");
            r.r.throughput_fps = v;
          },
          "Frames per second, frames in flight overlapping.")
      .def_property(
          "notes", [](const PyResult& r) { return r.r.notes; },
          [](PyResult& r, const std::vector<std::string>& v) { r.r.notes = v; }, "What the scheme reports of itself, as text.")
      .def_property_readonly(
          "gpm_busy_s", [](const PyResult& r) { return r.r.gpm_busy_s; }, "Each GPM's busy time, seconds.")
      .def_property_readonly(
          "inter_gpm_bytes", [](const PyResult& r) { return r.r.total_inter_gpm_bytes(); }, "Bytes moved between GPMs.");

  m.def("sort_last_framebuffers", &sort_last_framebuffers, py::arg("gpms"),
        "Framebuffers of a sort-last scheme: 0 is the final frame, 1 + g GPM g's own.");
  m.def(
      "vertical_strip_owner",
      [](int tile_x, int tiles_x, int gpms) {
        if (gpms < 1 || tiles_x < 1 || tile_x < 0 || tile_x >= tiles_x) bad("vertical_strip_owner: tile or GPMs out of range");
        return vertical_strip_owner(tile_x, tiles_x, gpms);
      },
      py::arg("tile_x"), py::arg("tiles_x"), py::arg("gpms"),
      "The GPM owning tile column `tile_x` when the frame is cut into one vertical strip of whole tile columns per GPM.");
  m.def(
      "sort_first",
      [](const std::shared_ptr<PySim>& s, const std::function<int(int, int, int)>& owner, const std::string& geometry) {
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
              const int gpm = owner(x, y, eye);
              if (gpm < 0 || gpm >= gpms) bad("sort_first: the owner gave GPM " + std::to_string(gpm) + ", which does not exist");
              return gpm;
            },
            g);
      },
      py::arg("sim"), py::arg("owner"), py::arg("geometry"),
      "Renders frame 0 sort-first, draw by draw, every tile by its owner(tile_x, tile_y, eye); geometry 'shared' "
      "(once per draw, SMP), 'duplicated_smp' or 'duplicated_per_eye' (schemes/sort_first.h).");
}

}  // namespace oovr::python
