// OO-VR's runtime (paper Section 5.2): the object-aware distribution engine
// at work on the GPMs. It holds at most oo.batch_queue batches assigned but
// not started; whenever a slot is free it gives the next batch to the GPM
// whose counters predict it free first (total: c0 * triangles of the batches
// it holds; elapsed: c1 * vertices transformed + c2 * pixels rendered so
// far, from the GPMs' progress), and that GPM's pre-allocation unit copies
// the batch's vertex, index and texture pages, in batch order. A GPM starts
// its next batch when it ends one (after the batch's copy). The first
// oo.warmup_batches batches of a run go round-robin with first-touch data,
// and their measured times fit c0, c1, c2 (least squares); a fit carried
// from an earlier frame predicts from the first batch. Fine-grained split:
// when every batch has been assigned and a GPM has nothing to do, it takes
// the later half of the chunks not yet started (whose object's geometry has
// been issued) of the GPM with the most, and its pre-allocation unit copies
// the textures they sample.
//
// Screen affinity (oo.affinity > 0; oovr's own idea, not the paper's):
// with the predictor running, a batch goes to the GPM for which its
// predicted free time plus the batch's link cost there is least, the cost
// being oo.affinity times the seconds its objects' pixels owned by other
// GPMs take on a link (given per object and GPM; an object without one
// costs nothing anywhere). A GPM with nothing to do still takes the next
// batch at once, whatever it costs: affinity never leaves a GPM idle.
//
// Without the predictor (OO_APP, Section 6.1: software only) there is no
// hardware engine and so no batch queue: the application deals every batch
// round-robin at once.
//
// A batch's work is, per object, one geometry item (both views, SMP), then
// its tile records in chunks of oo.tiles_per_unit tiles, which is the grain
// the split moves. The runtime decides; a RuntimeExecutor (the scheme,
// schemes/impl/oo.cpp) turns its decisions into work on the machine and
// reports when that work ends.
#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "oovr/framework/distribution.h"
#include "oovr/framework/middleware.h"
#include "oovr/framework/oo_spec.h"
#include "oovr/pipeline/frame_trace.h"

namespace oovr {

class RuntimeExecutor {
 public:
  virtual ~RuntimeExecutor() = default;
  virtual double now() const = 0;
  // Fraction of a unit's work done: 0 before it starts, 1 once done.
  virtual double progress(int unit) const = 0;
  // GPM `gpm`'s pre-allocation unit copies what `objects` sample (and their
  // vertex and index buffers when `geometry`), after unit `after` (-1:
  // none). Returns its unit, or -1 when nothing needed copying.
  virtual int preallocate(int gpm, const std::vector<uint32_t>& objects, bool geometry, int after) = 0;
  // GPM `gpm` starts a batch: the engine sends it the batch's draws
  // (`objects`, in order), which its front end may process ahead of the work.
  virtual void start_batch(int gpm, const std::vector<uint32_t>& objects) = 0;
  // Transforms `object` (both views) on `gpm` once unit `prealloc` (-1:
  // none) has ended. Returns its unit.
  virtual int geometry(int gpm, uint32_t object, int prealloc) = 0;
  // Renders `records` of `object` on `gpm` after its geometry unit
  // `geo_unit` (done on `geo_gpm`) and the copies `prealloc` and
  // `thief_copy` (-1: none). Returns its unit.
  virtual int chunk(int gpm, uint32_t object, std::span<const TileWork* const> records, int geo_unit, int geo_gpm, int prealloc,
                    int thief_copy) = 0;
  // For a timeline (nothing by default): batch `batch` went to `gpm`, `why`
  // ("round-robin", "predicted free first", "idle"), each GPM predicted
  // free in `predicted` seconds (with screen affinity, plus the batch's link
  // time there; empty when dealt round-robin); batch `batch` ran on its GPM
  // from unit `first` to unit `last` (its moved chunks elsewhere are not in
  // the span).
  // Whether the executor keeps these (a timeline): the runtime works out
  // its predictions for decided() only then.
  virtual bool keeps_marks() const { return false; }
  virtual void decided(int batch, int gpm, std::span<const double> predicted, const char* why) {
    (void)batch, (void)gpm, (void)predicted, (void)why;
  }
  virtual void batch_ran(int batch, int gpm, int first, int last) { (void)batch, (void)gpm, (void)first, (void)last; }
};

class OORuntime {
 public:
  // `records[o]`: object o's tile records, both views, in trace order;
  // `vertices[o]`: its vertices. `rates`: a fit carried from an earlier
  // frame (used only with the predictor). `link_seconds[o][g]`: what object
  // o's pixels cost the links when it is rendered on GPM g (screen
  // affinity; `link_seconds` or its row for o empty: nothing).
  OORuntime(const OOSpec& spec, int gpms, std::vector<Batch> batches, const std::vector<std::vector<const TileWork*>>& records,
            const std::vector<uint64_t>& vertices, RuntimeExecutor& executor, std::optional<Rates> rates,
            std::vector<std::vector<double>> link_seconds = {});
  OORuntime(const OORuntime&) = delete;
  OORuntime& operator=(const OORuntime&) = delete;

  // Issues the first work (call once, before the machine runs).
  void start() { schedule(); }
  // A unit ended: the GPM that ran it (if it was an item) moves on.
  void on_finish(int unit);

  const std::vector<Batch>& batches() const { return m_batches_in; }
  // The predictor, once it has rates (from the start when carried).
  const DistributionEngine* engine() const { return m_engine.get(); }
  // Rates fitted in this run, when the warm-up batches ended.
  const std::optional<Rates>& fitted() const { return m_fitted; }
  int moved_chunks() const { return m_moved; }
  // Batches screen affinity sent to another GPM than the one predicted free
  // first.
  int affine_batches() const { return m_affine; }
  // Whether every piece of work has been given to a GPM: nothing more will
  // be added but what follows it (a deferred composition).
  bool all_issued() const { return m_issued == m_items; }

 private:
  struct Item {
    uint32_t object = 0;
    int batch = 0;
    bool geometry = false;
    std::vector<const TileWork*> records;
    uint64_t vertices = 0, pixels = 0;  // what the GPM reports to the engine
    int thief_copy = -1;                // for a moved chunk: its new GPM's data copy
  };
  struct BatchRun {
    std::vector<Item> items;
    int gpm = -1;
    int items_left = 0;
    int prealloc = -1;
    double start = -1;
    bool warmup = false;
    double vertices_done = 0, pixels_done = 0;
    uint64_t pixels = 0;
    int first_unit = -1, last_unit = -1;  // its units on its own GPM
  };
  struct Gpm {
    std::deque<int> pending;  // batches assigned, not started
    int current = -1;         // the batch it works on
    std::deque<Item*> todo;   // its items of that batch not started
    int running = -1;         // unit of the item it runs
    Item* item = nullptr;
    int last_copy = -1;  // its pre-allocation unit's last copy (copies run in batch order)
  };

  void start_engine(const Rates& rates);
  int queued() const;
  int choose(int b);
  // Each GPM's predicted free time plus `extra` (empty: none), the engine
  // running.
  std::vector<double> predicted(const std::vector<double>& extra) const;
  void assign(int b, int g);
  void schedule();
  bool advance(int g);
  bool steal(int g);
  void issue(int g, Item& it);
  void batch_done(int b);

  OOSpec m_spec;
  int m_n;
  RuntimeExecutor& m_exec;
  std::vector<Batch> m_batches_in;
  std::vector<BatchRun> m_batches;
  std::vector<int> m_geo_unit, m_geo_gpm;
  std::vector<Gpm> m_gpm;
  std::vector<int> m_unit_gpm;  // per unit id: the GPM running it as an item, or -1
  std::unique_ptr<DistributionEngine> m_engine;
  std::optional<Rates> m_fitted;
  std::vector<BatchSample> m_samples;
  std::vector<std::vector<double>> m_link_seconds;
  int m_next = 0;
  int m_rr = 0;
  int m_moved = 0;
  int m_affine = 0;
  size_t m_items = 0, m_issued = 0;  // items in all batches, and issued
};

}  // namespace oovr
