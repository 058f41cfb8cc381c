// A run's timeline as Trace Event Format JSON (oovr simulate --timeline),
// which Perfetto (ui.perfetto.dev) and chrome://tracing open: what every
// unit of work did, where and when, frame after frame.
//
//   GPM g      one process per GPM: its front end receiving draws, its
//              pipeline (geometry and tile work), its ROPs composing, and
//              the copies its pre-allocation unit makes into it;
//   links      one thread per (sender, receiver) pair: the transfers;
//   frames     each measured frame as a span;
// and on a GPM's process, the scheme's own marks (TimelineMark): OO-VR's
// batches as spans on the GPM that ran them, and its engine's decisions
// (which GPM a batch went to, each GPM's predicted free time) as instants;
// CHOPIN's composition groups as spans on each GPM that worked in them;
// GPUpd's batches as a projection and a rendering span on each GPM.
//
// A unit's span is its start to its finish; its arguments split that into
// work and the latency after it (memory, link hops), and the latency is a
// span of its own inside it (category "wait"). Times are in
// microseconds, as the format has them. At most `max_events` units are
// written, the earliest first; the file says when more were left out.
#pragma once

#include <cstddef>
#include <string>

#include "oovr/schemes/i_scheme.h"

namespace oovr {

struct TimelineText {
  std::string json;
  size_t units = 0;    // units written
  size_t omitted = 0;  // units left out past max_events
  size_t waits = 0;    // wait spans written, one inside each unit written that waited
};

// `r` must have been run with MachineSpec::timeline. Throws Error when it
// holds no timeline.
TimelineText timeline_json(const SchemeResult& r, size_t max_events);

}  // namespace oovr
