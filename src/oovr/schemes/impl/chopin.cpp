// chopin (not in the OO-VR paper): Ren and Lis, "CHOPIN: Scalable Graphics
// Rendering in Multi-GPU Systems via Parallel Image Composition", HPCA
// 2021. Sort-last: every draw goes whole to one GPM, which renders it into
// a framebuffer of its own; the GPMs' sub-images are composed in parallel.
//
//   composition groups  the frame's draws split where blending switches on
//                       or off: opaque sub-images compose in any order
//                       (depth decides), blended ones only in draw order
//                       (the over operator is associative, not
//                       commutative). A group's sub-images are composed
//                       when its draws are rendered; the next group starts
//                       when that composition has ended (its draws test
//                       against, and blend over, the composed frame).
//                       `chopin.groups = frame` makes the frame one opaque
//                       group (a bound: blended draws composed out of
//                       order, which CHOPIN would not do).
//   draw scheduler      in an opaque group each draw goes, in API order, to
//                       the GPM with the fewest outstanding triangles
//                       (scheduled minus processed), among the GPMs whose
//                       front end has room for it (gpm.draws_ahead draws
//                       not yet finished). `chopin.scheduler = round-robin`
//                       deals draws in turn instead (an ablation). A
//                       blended group is cut into N runs of consecutive
//                       draws with about equal triangles, run g on GPM g,
//                       so that adjacent sub-images merge in order.
//   composition         CHOPIN's: the screen split among the N GPMs by
//                       halving its longer side, each GPM sending every
//                       other GPM its region in N-1 rounds, one send and
//                       one receive at a time (sort_last.composition =
//                       pairwise, schemes/composition.h; any other
//                       algorithm may be set instead).
//
// A draw is both eyes' (one multi-view draw: its vertices transformed
// once, SMP, its triangles set up for each eye), as the baseline draws.
//
// Assumed where the paper is silent or oovr cannot say: the GPMs' counts of
// processed triangles are exact and current (CHOPIN updates them
// periodically over the links; oovr takes a draw's processed share as its
// last unit's finished share), the scheduler's window is the front end's
// (gpm.draws_ahead), a group ends at every change of blending (the traces
// carry no other synchronisation point: render-target switches and clears
// are outside them), and the composition scheduler is a fixed rotation
// rather than CHOPIN's greedy pairing of idle senders and receivers. Not
// done: CHOPIN's optional splitting of large draws.
#include <algorithm>
#include <deque>
#include <limits>
#include <string>

#include "oovr/core/config_sections.h"
#include "oovr/schemes/composition.h"

namespace oovr {
namespace {

struct ChopinSettings {
  bool by_triangles = true;  // else round-robin
  bool by_blending = true;   // groups cut where blending switches; else one group

  static ChopinSettings from_config(const Config& c) {
    ChopinSettings s;
    s.by_triangles = c.get_choice("chopin.scheduler", "triangles", {"triangles", "round-robin"}) == "triangles";
    s.by_blending = c.get_choice("chopin.groups", "blending", {"blending", "frame"}) == "blending";
    return s;
  }
};

struct Group {
  uint32_t first = 0, end = 0;
  bool blended = false;
};

// Draws [first, end) cut where blending switches on or off (or, with
// `one`, the whole frame as one opaque group).
std::vector<Group> composition_groups(const FrameSim& sim, const FrameTrace& f, bool one) {
  std::vector<Group> groups;
  const std::vector<Object>& draws = sim.draws(f);
  for (uint32_t o = 0; o < draws.size(); ++o) {
    const bool blended = !one && sim.scene().pass_of(draws[o]).blended();
    if (groups.empty() || groups.back().blended != blended) groups.push_back({o, o, blended});
    groups.back().end = o + 1;
  }
  return groups;
}

// The dynamic part: draws given out as GPMs make room, groups closed and
// their compositions waited for, from the timing engine's progress.
class Scheduler {
 public:
  Scheduler(FrameSim& sim, Composer& composer, const ChopinSettings& set)
      : m_sim(sim),
        m_composer(composer),
        m_set(set),
        m_f(sim.frame()),
        m_groups(composition_groups(sim, m_f, !set.by_blending)),
        m_records(records_by_object(m_f, sim.draws(m_f).size())),
        m_outstanding(size_t(sim.gpms())),
        m_window(size_t(std::max(1, sim.timing().draws_ahead))) {
    if (!m_groups.empty()) enter(0);
  }

  // Gives out draws while it can; closes groups and waits at their ends.
  void pump() {
    while (m_group < m_groups.size()) {
      if (!m_barrier.empty()) return;
      const Group& g = m_groups[m_group];
      if (m_next == g.end) {
        // The group on each GPM, for a timeline: its first draw's command to
        // its last unit there.
        for (int gpm = 0; gpm < m_sim.gpms(); ++gpm)
          if (const auto [first, last] = m_span[size_t(gpm)]; first >= 0)
            m_sim.mark_span("group " + std::to_string(m_group) + (g.blended ? " (blended)" : " (opaque)"), "group", gpm, first,
                            last, {{"group", double(m_group)}, {"draws", double(g.end - g.first)}});
        for (int u : m_composer.close())
          if (!m_sim.engine().finished(u)) m_barrier.push_back(u);
        for (int gpm = 0; gpm < m_sim.gpms(); ++gpm) {
          const int u = m_sim.last_unit(gpm);
          if (u >= 0 && !m_sim.engine().finished(u)) m_barrier.push_back(u);
        }
        if (m_group + 1 < m_groups.size()) enter(m_group + 1);
        else ++m_group;
        continue;
      }
      const int gpm = choose(g);
      if (gpm < 0) return;
      dispatch(m_next++, gpm);
    }
  }

  void on_finish(int unit) {
    m_barrier.erase(std::remove(m_barrier.begin(), m_barrier.end(), unit), m_barrier.end());
    for (auto& q : m_outstanding)
      if (!q.empty() && q.front().last == unit) q.pop_front();
    pump();
  }

  size_t groups() const { return m_groups.size(); }
  size_t blended_groups() const {
    return size_t(std::count_if(m_groups.begin(), m_groups.end(), [](const Group& g) { return g.blended; }));
  }

 private:
  struct Draw {
    uint64_t triangles = 0;
    int last = -1;  // the draw's last unit on its GPM
  };

  void enter(size_t group) {
    m_group = group;
    const Group& g = m_groups[group];
    m_next = g.first;
    m_run.clear();
    m_span.assign(size_t(m_sim.gpms()), {-1, -1});
    if (!g.blended) return;
    // Runs of consecutive draws with about equal triangles: a draw goes to
    // the run its middle triangle falls in.
    uint64_t total = 0;
    for (uint32_t o = g.first; o < g.end; ++o) total += m_f.objects[o].triangles;
    const int n = m_sim.gpms();
    uint64_t before = 0;
    for (uint32_t o = g.first; o < g.end; ++o) {
      const uint64_t t = m_f.objects[o].triangles;
      const int run = total ? int((2 * before + t) * uint64_t(n) / (2 * total))
                            : int(uint64_t(o - g.first) * uint64_t(n) / (g.end - g.first));
      m_run.push_back(std::min(n - 1, run));
      before += t;
    }
  }

  // The GPM for the group's next draw, or -1 while none has room.
  int choose(const Group& g) {
    const int n = m_sim.gpms();
    const auto room = [&](int gpm) { return m_outstanding[size_t(gpm)].size() < m_window; };
    if (g.blended) {
      const int gpm = m_run[m_next - g.first];
      return room(gpm) ? gpm : -1;
    }
    if (!m_set.by_triangles) {
      const int gpm = (m_rr + 1) % n;
      if (!room(gpm)) return -1;
      m_rr = gpm;
      return gpm;
    }
    // Ties go to the first GPM after the last one chosen.
    int best = -1;
    double least = std::numeric_limits<double>::infinity();
    for (int k = 1; k <= n; ++k) {
      const int gpm = (m_rr + k) % n;
      if (!room(gpm)) continue;
      double left = 0;
      for (const Draw& d : m_outstanding[size_t(gpm)]) left += double(d.triangles) * m_sim.engine().work_left(d.last);
      if (left < least) {
        least = left;
        best = gpm;
      }
    }
    if (best >= 0) m_rr = best;
    return best;
  }

  void dispatch(uint32_t o, int gpm) {
    const ObjectWork& ow = m_f.objects[o];
    const int command = m_sim.command(gpm);
    int last = m_sim.geometry(gpm, o, 1, uint64_t(ow.setup[0]) + ow.setup[1]);
    std::vector<const TileWork*> records = m_records[o].both();
    if (!records.empty()) {
      FrameSim::TileJob job{gpm, std::move(records), 0, {last}};
      m_composer.target(job);
      last = m_sim.tiles_together({job}, m_f).front();
      m_composer.send(job, last);
    }
    m_sim.end_draw(gpm);
    m_outstanding[size_t(gpm)].push_back({ow.triangles, last});
    auto& span = m_span[size_t(gpm)];
    if (span.first < 0) span.first = command;
    span.second = last;
  }

  FrameSim& m_sim;
  Composer& m_composer;
  const ChopinSettings& m_set;
  const FrameTrace& m_f;
  std::vector<Group> m_groups;
  std::vector<ObjectRecords> m_records;
  std::vector<std::deque<Draw>> m_outstanding;  // per GPM, in dispatch order (a queue's units end in order)
  size_t m_window;
  size_t m_group = 0;
  uint32_t m_next = 0;                      // the next draw to give out
  int m_rr = -1;                            // the GPM chosen last
  std::vector<int> m_run;                   // per draw of a blended group: its GPM
  std::vector<int> m_barrier;               // units the next group waits for
  std::vector<std::pair<int, int>> m_span;  // per GPM: the group's first and last unit there (-1: none)
};

class Chopin final : public Scheme {
 public:
  SchemeResult run(const SchemeInput& in) const override {
    const ChopinSettings& set = in.spec->own<ChopinSettings>("chopin");
    FrameSim sim(in, sort_last_framebuffers(in.spec->memory.gpms));
    Composer composer(sim, sim.spec().composition, CompositionAlgorithm::pairwise);
    Scheduler scheduler(sim, composer, set);
    scheduler.pump();
    SchemeResult r = sim.finish("chopin", 1, [&](int unit) { scheduler.on_finish(unit); });
    r.add_own("groups", double(scheduler.groups()), "");
    r.add_own("groups.blended", double(scheduler.blended_groups()), "");
    r.notes.push_back(std::to_string(scheduler.groups()) + " composition groups (" + std::to_string(scheduler.blended_groups()) +
                      " blended); draws by " + (set.by_triangles ? "fewest outstanding triangles" : "round-robin") +
                      ", composition " + composition_algorithm_name(composer.algorithm()));
    return r;
  }
};

const ConfigSections::Add settings(
    "chopin", {"CHOPIN's settings (Ren and Lis, HPCA 2021)",
               nullptr,
               {{"chopin.scheduler",
                 "an opaque group's draws to the GPM with the fewest outstanding triangles (CHOPIN's draw scheduler) or "
                 "round-robin"},
                {"chopin.groups",
                 "composition groups cut where blending switches on or off (blending), or the frame one opaque group "
                 "(frame: a bound, blended draws then composed out of order)"}},
               true,
               [](const Config& c) { return std::any(ChopinSettings::from_config(c)); }});

const Schemes::Add reg("chopin", {"CHOPIN: draws whole to the least-loaded GPM, composition groups, parallel image composition "
                                  "(HPCA 2021)",
                                  [] { return std::make_unique<Chopin>(); },
                                  150,
                                  {"chopin", "sort_last"}});

}  // namespace
}  // namespace oovr
