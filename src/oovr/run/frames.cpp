#include "oovr/run/frames.h"

#include <sys/statvfs.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <new>
#include <numeric>

#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/out_of_memory.h"
#include "oovr/core/text.h"
#include "oovr/memory/memory_spec.h"
#include "oovr/pipeline/trace_cache.h"

namespace oovr {
namespace fs = std::filesystem;

namespace {

uint64_t memory_budget(const WindowRequest& r) { return r.memory_budget ? r.memory_budget : trace_memory_budget(); }

}  // namespace

uint64_t trace_memory_budget() {
  const char* env = std::getenv("OOVR_TRACE_MEMORY_MB");
  if (!env || !*env) return uint64_t(4096) << 20;
  const auto mb = parse_whole_number(env, 1, 999999999);
  if (!mb)
    throw Error(std::string("OOVR_TRACE_MEMORY_MB must be a whole number of megabytes from 1 to 999999999, not '") + env + "'");
  return *mb << 20;
}

uint64_t trace_bytes(const FrameTrace& t) {
  return t.objects.size() * sizeof(ObjectWork) + t.tiles.size() * sizeof(TileWork) + t.tex_lines.size() * sizeof(TexLine);
}

uint64_t window_bytes(const FrameWindow& w) {
  uint64_t b = 0;
  for (const FrameOutput& o : w.outputs) b += trace_bytes(o.trace);
  return b;
}

namespace {

// A window's traces on disk, one file each, read back on demand; the folder
// is removed with the last holder of the sequence.
class StreamedFrames final : public FrameSequence {
 public:
  explicit StreamedFrames(fs::path dir) : m_dir(std::move(dir)) {}
  ~StreamedFrames() override {
    std::error_code ec;
    fs::remove_all(m_dir, ec);
  }
  size_t size() const override { return m_count; }
  std::shared_ptr<const FrameTrace> at(size_t k) const override {
    if (k >= m_count) throw Error("frame " + std::to_string(k) + " of a streamed window of " + std::to_string(m_count));
    const std::string path = file(k);
    const std::string bytes = read_input_file(path, "streamed trace", uint64_t(1) << 40);
    std::string why;
    auto t = decode_entry(bytes, key(k), &why);
    if (!t) throw Error("streamed trace '" + path + "' changed during the run: " + why);
    return std::make_shared<const FrameTrace>(std::move(*t));
  }
  void add(const FrameTrace& t) {
    write_output_file(file(m_count), encode_entry(key(m_count), t), "streamed trace");
    ++m_count;
  }
  const fs::path& directory() const { return m_dir; }

 private:
  static std::string key(size_t k) { return "frame-" + std::to_string(k); }
  std::string file(size_t k) const { return (m_dir / (key(k) + ".trace")).string(); }

  fs::path m_dir;
  size_t m_count = 0;
};

// A fresh folder for a streamed window in the trace cache's folder, named
// as the cache's temporaries are (removed by a later store if this process
// dies first), after checking that `bytes` fit on its disk.
fs::path stream_folder(const TraceCache& cache, uint64_t bytes, int count) {
  static std::atomic<int> serial{0};
  const std::string cache_dir = cache.directory();
  const fs::path dir = cache.temporary_path("window-" + std::to_string(serial++));
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec)
    throw Error("cannot stream the traces of " + std::to_string(count) + " frames: cannot create '" + dir.string() +
                "': " + ec.message());
  struct statvfs st {};
  if (::statvfs(dir.c_str(), &st) == 0) {
    const uint64_t free = uint64_t(st.f_bavail) * uint64_t(st.f_frsize);
    if (bytes > free) {
      fs::remove_all(dir, ec);
      throw Error("the traces of " + std::to_string(count) + " frames need about " + std::to_string(bytes >> 20) +
                  " MB, more than the memory budget ($OOVR_TRACE_MEMORY_MB) and than the " + std::to_string(free >> 20) +
                  " MB free in " + cache_dir + " ($OOVR_CACHE_DIR): use fewer frames or a larger disk");
    }
  }
  return dir;
}

}  // namespace

int measured_window(const std::vector<SchemeRef>& schemes, const MachineSpec& spec, int frames, const std::string& what) {
  for (const auto& s : schemes) check_scheme_config(s, spec);  // before any trace is rendered
  if (frames > 0) {
    for (const auto& s : schemes) {
      const int m = scheme_frames_needed(s, spec);
      if (frames % m != 0)
        throw Error(what + " " + std::to_string(frames) + ": " + s.name + " renders " + std::to_string(m) +
                    " frames at once (one per GPM), so " + what + " must be a multiple of " + std::to_string(m));
    }
    return frames;
  }
  int w = spec.memory.gpms;
  for (const auto& s : schemes) w = std::lcm(w, scheme_frames_needed(s, spec));
  return w;
}

int measured_window(const std::vector<std::string>& schemes, const MachineSpec& spec, int frames, const std::string& what) {
  std::vector<SchemeRef> refs;
  for (const auto& s : schemes) refs.push_back(find_scheme(s));
  return measured_window(refs, spec, frames, what);
}

int measured_window(const std::vector<std::string>& schemes, const Config& config, int frames, const std::string& what) {
  return measured_window(schemes, MachineSpec::from_config(config), frames, what);
}

PipelineSettings trace_settings(const MachineSpec& spec, int aniso) {
  PipelineSettings p = spec.pipeline;
  p.max_anisotropy = aniso;
  p.line_bytes = uint32_t(spec.memory.line.value);
  p.validate();
  return p;
}

FrameWindow load_window(std::shared_ptr<const Scene> scene, const StereoRig& rig, const Config& config, const WindowRequest& r) {
  return load_window(std::move(scene), rig, MachineSpec::from_config(config), r);
}

namespace {

// load_window's work, into `f` (its scene and rig set): a trace handed to
// `ready` lives in `f`, which outlives an error thrown here, so that whoever
// holds the trace may still read it (WindowLoader).
void fill_window(FrameWindow& f, const MachineSpec& spec, const WindowRequest& r, const FrameReady& ready) {
  const StereoRig& rig = f.rig;
  const PipelineSettings p = trace_settings(spec, r.aniso);
  const Scene& sc = *f.scene;
  const int path = int(sc.camera.frames.size());
  if (r.first < 0 || r.first >= path)
    throw Error("frame " + std::to_string(r.first) + " is out of range: the camera path has " + std::to_string(path) + " frames");
  const uint64_t budget = memory_budget(r);
  const TraceCache cache;
  const uint64_t fingerprint = r.use_cache ? scene_fingerprint(sc) : 0;
  std::vector<std::string> rejected;  // entries that did not verify
  std::unique_ptr<StreamedFrames> stream;
  uint64_t held = 0;  // bytes of traces in memory
  // Room for every frame at once: a trace handed to `ready` stays where it is.
  f.outputs.reserve(size_t(r.count));
  for (int k = 0; k < r.count; ++k) {
    const int frame = (r.first + k) % path;
    FrameOutput out;
    try {
      const StereoView view = make_stereo_view(sc.camera, frame, f.rig);
      const std::string key = cache.key(fingerprint, frame, view, p);
      bool hit = false;
      if (r.use_cache && !(k == 0 && r.need_first_image)) {
        TraceLookup found = cache.load(key, sc, frame, view, p);
        if (!found.rejected.empty()) rejected.push_back(std::move(found.rejected));
        if (found.trace) {
          out.trace = std::move(*found.trace);
          ++f.cached;
          hit = true;
        }
      }
      if (!hit) {
        // Only the first frame's picture is ever used (GPM and traffic
        // images), and only when asked for: the others are drawn as the
        // trace alone, the same trace in less time (PipelineSettings::draw_image).
        PipelineSettings drawn = p;
        drawn.draw_image = k == 0 && r.need_first_image;
        out = render_frame(sc, view, drawn, frame);
        if (r.use_cache) cache.store(key, out.trace);
      }
    } catch (const std::bad_alloc&) {
      throw Error(out_of_memory_message("rendering frame " + std::to_string(frame) + " of " + sc.name + " at " +
                                        std::to_string(rig.frame_width()) + "x" + std::to_string(rig.frame_height()) + ", with " +
                                        std::to_string(held >> 20) + " MB of traces held"));
    }
    const uint64_t bytes = trace_bytes(out.trace);
    // Decided on the first trace: the window's size is about count times it.
    if (k == 0 && bytes * uint64_t(r.count) > budget && r.count > 1) {
      stream = std::make_unique<StreamedFrames>(stream_folder(cache, bytes * uint64_t(r.count), r.count));
      f.streamed = true;
      f.notes.push_back("traces of " + std::to_string(r.count) + " frames (about " +
                        std::to_string((bytes * uint64_t(r.count)) >> 20) + " MB) streamed through " +
                        stream->directory().string() + ", beyond the memory budget of " + std::to_string(budget >> 20) +
                        " MB ($OOVR_TRACE_MEMORY_MB)");
    }
    if (stream) {
      stream->add(out.trace);
      if (k == 0) f.outputs.push_back(std::move(out));  // its picture, for the GPM and traffic images
    } else {
      held += bytes;
      f.outputs.push_back(std::move(out));
      if (ready) ready(size_t(k), f.outputs.back().trace);
    }
  }
  if (stream) {
    f.frames = std::shared_ptr<const FrameSequence>(std::move(stream));
  } else {
    for (const auto& o : f.outputs) f.traces.push_back(&o.trace);
    f.frames = std::make_shared<FramesInMemory>(f.traces);
  }
  // Once per window, however many entries: they were rendered again, so the
  // results are those of an uncached run.
  if (!rejected.empty()) {
    std::string note = "trace cache " + cache.directory() + ": " + std::to_string(rejected.size()) +
                       (rejected.size() == 1 ? " entry" : " entries") + " did not verify and " +
                       (rejected.size() == 1 ? "was" : "were") + " rendered again (" + rejected.front();
    if (rejected.size() > 1) note += "; and " + std::to_string(rejected.size() - 1) + " more";
    f.notes.push_back(note + ")");
  }
}

}  // namespace

FrameWindow load_window(std::shared_ptr<const Scene> scene, const StereoRig& rig, const MachineSpec& spec, const WindowRequest& r,
                        const FrameReady& ready) {
  if (!scene) throw Error("load_window: no scene");
  FrameWindow f{std::move(scene), rig, {}, {}, nullptr, 0, false, {}};
  fill_window(f, spec, r, ready);
  return f;
}

WindowLoader::WindowLoader(std::shared_ptr<const Scene> scene, const StereoRig& rig, const MachineSpec& spec,
                           const WindowRequest& r)
    : m_count(size_t(std::max(r.count, 0))), m_frames(*this), m_ready(m_count, nullptr) {
  if (!scene) throw Error("WindowLoader: no scene");
  m_thread = std::thread([this, scene = std::move(scene), rig, spec, r] {
    const auto t0 = std::chrono::steady_clock::now();
    // Held by the loader whatever happens: the traces handed out live in it.
    m_filling = std::make_shared<FrameWindow>(FrameWindow{scene, rig, {}, {}, nullptr, 0, false, {}});
    std::exception_ptr error;
    try {
      fill_window(*m_filling, spec, r, [this](size_t k, const FrameTrace& t) {
        const std::lock_guard<std::mutex> lock(m_mutex);
        if (k < m_ready.size()) m_ready[k] = &t;
        m_changed.notify_all();
      });
    } catch (...) {
      error = std::current_exception();
    }
    const std::lock_guard<std::mutex> lock(m_mutex);
    m_error = error;
    m_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    m_done = true;
    m_changed.notify_all();
  });
}

WindowLoader::~WindowLoader() {
  if (m_thread.joinable()) m_thread.join();
}

std::shared_ptr<const FrameWindow> WindowLoader::wait() {
  if (m_thread.joinable()) m_thread.join();
  if (m_error) std::rethrow_exception(m_error);
  return m_filling;
}

size_t WindowLoader::Frames::size() const { return m_owner.m_count; }

std::shared_ptr<const FrameTrace> WindowLoader::Frames::at(size_t k) const {
  if (k >= m_owner.m_count) throw Error("frame " + std::to_string(k) + " of a window of " + std::to_string(m_owner.m_count));
  std::unique_lock<std::mutex> lock(m_owner.m_mutex);
  m_owner.m_changed.wait(lock, [&] { return m_owner.m_ready[k] || m_owner.m_done; });
  // A trace in memory: it stays in the window, which the loader holds.
  if (const FrameTrace* t = m_owner.m_ready[k]) return std::shared_ptr<const FrameTrace>(std::shared_ptr<const FrameTrace>(), t);
  if (m_owner.m_error) std::rethrow_exception(m_owner.m_error);
  const std::shared_ptr<const FrameWindow> window = m_owner.m_filling;  // whole: the loader is done
  lock.unlock();
  return window->frames->at(k);  // streamed: read back once the whole window is written
}

}  // namespace oovr
