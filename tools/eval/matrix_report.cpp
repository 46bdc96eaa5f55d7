#include "tools/eval/matrix_report.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "tools/eval/text_fields.hpp"

namespace tumble::eval {
namespace {

std::string number(double value, const char* format = "%.2f") {
  if (!std::isfinite(value)) return "";
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::optional<BoxStats> stats_of(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  return box_stats(values);
}

// "median | Q1 | Q3 | max" cells, or dashes.
std::string box_cells(const std::optional<BoxStats>& stats) {
  if (!stats) return " – | – | – | – |";
  return " " + number(stats->median) + " | " + number(stats->q1) + " | " + number(stats->q3) + " | " +
         number(stats->max) + " |";
}

const CellSummary* find_cell(const std::vector<CellSummary>& cells, const Variant& variant) {
  for (const CellSummary& cell : cells)
    if (cell.variant == variant) return &cell;
  return nullptr;
}

// The paper's comparisons (§V-B), measured on this bench, when both cells have data.
std::string paper_comparison(const std::vector<CellSummary>& cells) {
  const auto median = [&](const std::string& model, bool deskew, bool rotation) -> std::optional<double> {
    const CellSummary* cell = find_cell(cells, Variant{model, deskew});
    if (cell == nullptr) return std::nullopt;
    const auto& stats = rotation ? cell->rotation_deg_per_m : cell->translation_cm_per_m;
    if (!stats) return std::nullopt;
    return stats->median;
  };
  std::string text;
  for (const bool deskew : {false, true}) {
    const auto t = median("NM", deskew, false), r = median("NM", deskew, true);
    if (t && r)
      text += std::string("| NM ") + (deskew ? "with" : "without") + " de-skew, median | " + number(*t) + " cm/m, " +
              number(*r) + " deg/m | " + (deskew ? "3.11 cm/m, 0.79 deg/m" : "27.23 cm/m, 7.04 deg/m") + " |\n";
  }
  const auto line = [&](const std::string& what, const std::string& paper, const std::string& model_a, bool deskew_a,
                        const std::string& model_b, bool deskew_b, bool as_reduction) {
    const auto ta = median(model_a, deskew_a, false), tb = median(model_b, deskew_b, false);
    const auto ra = median(model_a, deskew_a, true), rb = median(model_b, deskew_b, true);
    if (!ta || !tb || !ra || !rb) return;
    std::string here;
    if (as_reduction)
      here = number(100.0 * (1.0 - *tb / *ta), "%.1f") + " % / " + number(100.0 * (1.0 - *rb / *ra), "%.1f") + " %";
    else
      here = number(*ta / *tb, "%.2f") + "× / " + number(*ra / *rb, "%.2f") + "×";
    text += "| " + what + " | " + here + " | " + paper + " |\n";
  };
  line("NM → VTW without de-skew (median error divided by)", "2.2× / 3.0×", "NM", false, "VTW", false, false);
  line("NM → GVTW with de-skew (median error reduced by)", "9.26 % / 21.84 %", "NM", true, "GVTW", true, true);
  line("NM: without → with de-skew (median error divided by)", "8.8× / 8.9×", "NM", false, "NM", true, false);
  line("NM → SAW with de-skew (median error reduced by)", "no improvement", "NM", true, "SAW", true, true);
  if (text.empty()) return "";
  return "## Against the paper (translation / rotation)\n\n| comparison | this bench | paper |\n|---|---|---|\n" +
         text + "\n";
}

}  // namespace

std::vector<CellSummary> summarize_cells(const std::vector<RunResult>& results, const std::vector<Variant>& variants) {
  std::vector<CellSummary> cells;
  for (const Variant& variant : variants) {
    CellSummary cell;
    cell.variant = variant;
    std::vector<double> translation, rotation, rpe_translation, rpe_rotation;
    for (const RunResult& result : results) {
      if (!(result.variant == variant)) continue;
      ++cell.runs;
      if (result.status == RunStatus::Failed) ++cell.failed;
      if (result.status == RunStatus::Diverged) ++cell.diverged;
      if (result.status != RunStatus::Ok) continue;
      ++cell.ok;
      const DriftResult& drift = *result.drift;
      translation.push_back(drift.translation_cm_per_m);
      rotation.push_back(drift.rotation_deg_per_m);
      if (drift.rpe_segments > 0) {
        rpe_translation.push_back(drift.rpe_translation_cm_per_m);
        rpe_rotation.push_back(drift.rpe_rotation_deg_per_m);
      }
    }
    cell.translation_cm_per_m = stats_of(translation);
    cell.rotation_deg_per_m = stats_of(rotation);
    cell.rpe_translation_cm_per_m = stats_of(rpe_translation);
    cell.rpe_rotation_deg_per_m = stats_of(rpe_rotation);
    cells.push_back(std::move(cell));
  }
  return cells;
}

std::string results_markdown(const MatrixDescription& description, const std::vector<CellSummary>& cells,
                             const std::vector<RunResult>& results) {
  const DivergenceLimits& limits = description.options.limits;
  std::string md = "# tumble-eval matrix\n\n";
  md += "Bench `" + description.bench_dir + "`, " + std::to_string(description.runs) + " runs (" +
        description.selection + "), " + std::to_string(results.size()) + " jobs.\n\n";
  md +=
      "Error of a run = final pose error / distance travelled (paper §V-B): the estimate is aligned to ground "
      "truth at its first pose, the error is taken at its last pose, the distance is along ground truth "
      "between the two. RPE = mean over " +
      number(description.options.drift.segment_m, "%g") +
      " m segments of travelled distance, per metre. Statistics over ok runs; quartiles by linear "
      "interpolation (type 7). Diverged: tumbled ran but its estimate is lost (fewer than 2 poses, last pose "
      "more than " +
      number(limits.max_end_gap_s, "%g") + " s before the end, or error above " +
      number(limits.translation_cm_per_m, "%g") + " cm/m or " + number(limits.rotation_deg_per_m, "%g") +
      " deg/m). Failed: could not be evaluated (missing or corrupt input, tumbled error).\n\n";

  md += "## Final pose error\n\n";
  md += "| de-skew | model | ok | diverged | failed | cm/m median | Q1 | Q3 | max | deg/m median | Q1 | Q3 | max |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const CellSummary& cell : cells) {
    md += "| " + std::string(cell.variant.deskew ? "yes" : "no") + " | " + cell.variant.model + " | " +
          std::to_string(cell.ok) + " | " + std::to_string(cell.diverged) + " | " + std::to_string(cell.failed) + " |" +
          box_cells(cell.translation_cm_per_m) + box_cells(cell.rotation_deg_per_m) + "\n";
  }
  md += "\n## Relative pose error over " + number(description.options.drift.segment_m, "%g") + " m\n\n";
  md += "| de-skew | model | cm/m median | Q1 | Q3 | max | deg/m median | Q1 | Q3 | max |\n";
  md += "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const CellSummary& cell : cells) {
    md += "| " + std::string(cell.variant.deskew ? "yes" : "no") + " | " + cell.variant.model + " |" +
          box_cells(cell.rpe_translation_cm_per_m) + box_cells(cell.rpe_rotation_deg_per_m) + "\n";
  }
  md += "\n";
  md += paper_comparison(cells);
  if (!description.box_plot_file.empty()) md += "![final pose error per model](" + description.box_plot_file + ")\n\n";

  std::string problems;
  for (const RunResult& result : results) {
    if (result.status == RunStatus::Ok) continue;
    problems += "| " + result.run + " | " + result.variant.label() + " | " + to_string(result.status) + " | " +
                result.message + " |\n";
  }
  if (!problems.empty())
    md += "## Runs not evaluated\n\n| run | variant | status | why |\n|---|---|---|---|\n" + problems + "\n";
  return md;
}

void write_runs_csv(const std::filesystem::path& path, const std::vector<RunResult>& results) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
  out << "run,kind,model,deskew,status,message,poses,scans,registered_scans,distance_m,translation_error_m,"
         "rotation_error_deg,translation_cm_per_m,rotation_deg_per_m,rpe_segments,rpe_translation_cm_per_m,"
         "rpe_rotation_deg_per_m,duration_s,wall_s,realtime_multiple,peak_rss_mib,trajectory,runaway_growth_m\n";
  for (const RunResult& r : results) {
    const bool ran = r.child.start_error.empty();
    out << csv_field(r.run) << ',' << csv_field(r.kind) << ',' << r.variant.model << ',' << (r.variant.deskew ? 1 : 0)
        << ',' << to_string(r.status) << ',' << csv_field(r.message) << ',';
    if (r.drift) {
      const DriftResult& d = *r.drift;
      out << d.poses << ',' << r.scans << ',' << r.registered_scans << ',' << number(d.distance_m, "%.4f") << ','
          << number(d.final_translation_error_m, "%.5f") << ',' << number(d.final_rotation_error_deg, "%.4f") << ','
          << number(d.translation_cm_per_m, "%.4f") << ',' << number(d.rotation_deg_per_m, "%.4f") << ','
          << d.rpe_segments << ',' << number(d.rpe_translation_cm_per_m, "%.4f") << ','
          << number(d.rpe_rotation_deg_per_m, "%.4f") << ',';
    } else {
      out << ',' << r.scans << ',' << r.registered_scans << ",,,,,,,,,";
    }
    out << number(r.duration_s, "%.3f") << ',' << (ran ? number(r.child.wall_s, "%.3f") : "") << ','
        << number(r.realtime_multiple(), "%.2f") << ','
        << (ran ? number(static_cast<double>(r.child.peak_rss_kib) / 1024.0, "%.1f") : "") << ','
        << csv_field(r.trajectory.string()) << ',' << (r.runaway ? number(r.runaway->growth_m(), "%.4f") : "")
        << '\n';
  }
  if (!out) throw std::runtime_error(path.string() + ": write error");
}

}  // namespace tumble::eval
