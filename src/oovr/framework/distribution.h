// The object-aware runtime distribution engine (paper Section 5.2): a
// micro-controller that predicts how long each batch takes, sends each batch
// to the GPM predicted to be free first, and has the GPMs' pre-allocation
// units copy the batch's data ahead of use.
//
// Equation 3: t(X) = c0 * #triangles = c1 * #transformed vertices + c2 *
// #rendered pixels. Per GPM, a total counter adds c0 * triangles for every
// batch it is given; an elapsed counter adds c1 per vertex transformed and c2
// per pixel rendered as the GPM reports its work. Their distance is the
// predicted time until the GPM is free. The first batches (8) go
// round-robin, and their measured times fit c0, c1 and c2.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace oovr {

// One finished batch: its size and how long it took.
struct BatchSample {
  double triangles = 0, vertices = 0, pixels = 0, seconds = 0;
};

struct Rates {
  double c0 = 0;  // seconds per triangle (total-time prediction)
  double c1 = 0;  // seconds per transformed vertex (elapsed time)
  double c2 = 0;  // seconds per rendered pixel (elapsed time)
  // Least squares through the origin: c0 from (triangles, seconds); c1 and
  // c2 together from (vertices, pixels, seconds), constrained to be >= 0
  // (when the joint fit gives a negative rate, the better single-variable fit
  // is kept). Needs at least one sample with work.
  static Rates fit(std::span<const BatchSample> samples);
};

class DistributionEngine {
 public:
  DistributionEngine(int gpms, const Rates& rates);

  // Batch `id` (of `triangles`) goes to `gpm`: its total counter grows.
  void assign(int id, int gpm, uint64_t triangles);
  // A batch ended: its share of both counters is dropped.
  void finish(int id);
  // The GPM's elapsed counter for the batches it holds, from the work it has
  // reported for them (c1 * vertices + c2 * pixels).
  void set_elapsed(int gpm, double vertices, double pixels);
  // Predicted time until `gpm` is free: total - elapsed, at least 0, and 0
  // when it holds no batch.
  double remaining(int gpm) const;
  // The GPM predicted to be free first (ties: the one holding fewer
  // batches, then the lowest id).
  int earliest_free() const;
  // The GPM for which remaining(g) + extra[g] is least (ties as above):
  // `extra` is a cost in seconds the batch has on each GPM beyond its
  // work, e.g. the link time of its pixels composed elsewhere (empty: none).
  int cheapest(std::span<const double> extra) const;
  const Rates& rates() const { return m_rates; }

 private:
  struct Held {
    int id, gpm;
    double predicted;
  };
  Rates m_rates;
  std::vector<Held> m_held;
  std::vector<double> m_elapsed;
};

// Storage of the engine (Section 5.4): two 64-bit counters per GPM, a 16-bit
// batch id per batch-queue entry, and three 32-bit registers per GPM
// (triangles, transformed vertices, rendered pixels of its current batch).
// 960 bits for 4 GPMs and a queue of 4, as the paper states.
struct EngineStorage {
  int counter_bits, batch_id_bits, register_bits;
  int total() const { return counter_bits + batch_id_bits + register_bits; }
};
EngineStorage engine_storage(int gpms, int batch_queue);

}  // namespace oovr
