// oovr paper and oovr beyond: an evaluation as a sweep (experiments/
// paper.toml, experiments/beyond.toml), run into a database in --out, and
// its document written from it (docs/paper-comparison.md,
// docs/beyond-paper.md when asked with --doc).
#include <fmt/core.h>

#include <filesystem>
#include <optional>

#include "commands.h"
#include "oovr/core/error.h"
#include "oovr/core/files.h"
#include "oovr/core/text.h"
#include "oovr/experiments/beyond.h"
#include "oovr/experiments/paper.h"
#include "oovr/experiments/results_db.h"
#include "oovr/experiments/svg_chart.h"
#include "oovr/experiments/sweep.h"
#include "progress.h"

namespace oovr::cli {

namespace fs = std::filesystem;

namespace {

// What differs between the evaluations: the sweep oovr carries, the
// writers, and the names of the document and of its plots' folder.
struct Evaluation {
  std::string command;    // "paper", "beyond"
  std::string title;      // "the paper", "the study", as messages name it
  std::string (*text)();  // the sweep oovr carries
  std::string file;       // its name in the repository
  std::string doc;        // the document's file name in --out
  std::string plots;      // the plots' folder under img/
  void (*outputs)(const PaperResults&, const PaperOptions&, const std::string& dir);
  void (*plot)(const PaperResults&, const PaperOptions&, const std::string& dir);
  void (*write_doc)(const PaperResults&, const PaperOptions&, const std::string& path, const std::string& plots_dir);
};

int evaluate(const PaperArgs& a, const Evaluation& e) {
  PaperOptions o;
  // The sweep on its machine: every point on the preset and --set's keys
  // (and the file's [set]), its own settings on top.
  try {
    if (a.sweep.empty()) load_evaluation(o, e.text(), e.file, "", a.config, a.settings, a.frames);
    else
      load_evaluation(o, read_input_file(a.sweep, "sweep", uint64_t(1) << 20), a.sweep, fs::path(a.sweep).parent_path().string(),
                      a.config, a.settings, a.frames);
  } catch (const Error& err) {
    // AFR on more GPMs than the file's frames: the window is an option here.
    const std::string what = err.what();
    if (what.find("so frames must be a multiple of") == std::string::npos) throw;
    throw Error(what + " (--frames sets every point's)");
  }
  o.only_scenes = split_list(a.scenes);
  o.jobs = a.jobs;
  o.command = a.command;
  // Fail before the work, not after: the outputs must be writable.
  if (a.out.empty()) throw Error("--out is empty: the evaluation's database and results need a folder");
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) throw Error("cannot create the folder '" + a.out + "': " + ec.message());
  if (!a.doc.empty()) check_output_path(a.doc, "comparison document (--doc)");
  // The other machine's database is read before the work, so that a wrong
  // path or sweep is said at once; its runs are read when written up.
  std::optional<Config> other_machine;
  if (!a.against.empty()) other_machine = paper_against_machine(a.against, o.sweep.name);
  o.db = (fs::path(a.out) / (o.sweep.name + ".db")).string();
  if (!a.against.empty() && fs::exists(o.db, ec) && fs::equivalent(a.against, o.db, ec))
    throw Error("--against " + a.against + " is this run's own database: give another --out, or the other machine's database");
  // Results of another build must not be mixed in: a new run starts afresh,
  // removing the database of an earlier one, but never one that holds
  // anything else (another sweep, or a file that is not oovr's).
  if (!a.resume && fs::exists(fs::symlink_status(o.db, ec))) {
    {
      const ResultsDb earlier(o.db, ResultsDb::Access::read_only);
      std::string others;
      for (const auto& [name, definition] : earlier.sweep_definitions())
        if (name != o.sweep.name) others += (others.empty() ? "'" : ", '") + name + "'";
      if (!others.empty())
        throw Error("the database '" + o.db + "' holds other sweeps (" + others + "), which a new run of " + e.title +
                    " would delete: move it away, or give --resume to add to it");
    }
    fs::remove(o.db, ec);
    if (ec) throw Error("cannot remove the earlier database '" + o.db + "': " + ec.message());
  }
  Progress progress(0);
  o.on_plan = [&](size_t points) {
    if (!o.sweep.shared.empty())
      fmt::print("{}: {} {} the same run as an earlier point (the machine's own value swept), run once and shared\n", e.command,
                 o.sweep.shared.size(), o.sweep.shared.size() == 1 ? "point is" : "points are");
    fmt::print("{}: sweep '{}': {} points to run into {}\n", e.command, o.sweep.name, points, o.db);
    std::fflush(stdout);
    progress.set_total(points);
  };
  o.progress = [&](const std::string& line) { progress.status(line); };
  o.on_record = [&](const RunRecord& r) { progress.point(r); };
  const PaperResults r = run_paper(o);
  progress.finish();
  e.outputs(r, o, a.out);
  // The document and its plots in --out; with --doc, also there, its plots
  // beside it, so that it can be committed without the raw results.
  const std::string out_plots = (fs::path(a.out) / "img" / e.plots).string();
  e.plot(r, o, out_plots);
  // For a paper or a slide: each chart as PDF and PNG too, here only (the
  // document in the repository shows the SVG).
  // Without rsvg-convert (librsvg2-bin) the run's results are not lost for
  // it: the charts stay SVG only, and the last line says why.
  size_t converted = 0;
  std::string unconverted;
  try {
    converted = write_pdf_and_png(out_plots);
  } catch (const Error& err) {
    unconverted = err.what();
  }
  e.write_doc(r, o, (fs::path(a.out) / e.doc).string(), out_plots);
  if (other_machine) write_paper_against(r, o, a.against, *other_machine, a.out);
  if (!a.doc.empty()) {
    const std::string plots = (fs::absolute(a.doc).parent_path() / "img" / e.plots).string();
    e.plot(r, o, plots);
    e.write_doc(r, o, a.doc, plots);
  }
  fmt::print("{} scenes ({} skipped), {} runs ({} run now) in {:.0f} s; database, results, CSV, plots ({}) and {} in {}{}\n",
             r.scenes.size(), r.skipped.size(), r.runs.size(), r.ran, r.seconds,
             unconverted.empty() ? fmt::format("{} charts as SVG, PDF and PNG", converted) : std::string("SVG only"), e.doc,
             a.out, a.doc.empty() ? "" : "; document also in " + a.doc);
  if (!a.against.empty())
    fmt::print("the claims beside those of {}: paper-against.md and claims-against.csv in {}\n", printable(a.against),
               printable(a.out));
  if (!unconverted.empty()) fmt::print("  note: {}\n", unconverted);
  for (const auto& s : r.skipped) fmt::print("  skipped: {}\n", s);
  return 0;
}

}  // namespace

int paper(const PaperArgs& a) {
  return evaluate(a, {"paper", "the paper", paper_sweep_text, "experiments/paper.toml", "paper-comparison.md", "paper",
                      write_paper_outputs, write_paper_plots, write_paper_doc});
}

int beyond(const PaperArgs& a) {
  return evaluate(a, {"beyond", "the study", beyond_sweep_text, "experiments/beyond.toml", "beyond-paper.md", "beyond",
                      write_beyond_outputs, write_beyond_plots, write_beyond_doc});
}

}  // namespace oovr::cli
