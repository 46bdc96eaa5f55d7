#include "tools/eval/box_plot.hpp"

#include <cstdio>
#include <optional>

#include "tools/eval/gnuplot.hpp"
#include "tools/eval/tumbled_job.hpp"

namespace tumble::eval {
namespace {

// Matplotlib's first five colours; NM in blue as in the paper's figure.
constexpr const char* kModelColours[] = {"0x1f77b4", "0xff7f0e", "0x2ca02c", "0xd62728", "0x9467bd"};

std::string number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

const std::optional<BoxStats>& panel_stats(const CellSummary& cell, bool rotation) {
  return rotation ? cell.rotation_deg_per_m : cell.translation_cm_per_m;
}

}  // namespace

std::string box_plot_script(const std::vector<CellSummary>& cells, const std::filesystem::path& png_path) {
  std::string script = "# tumble-eval box plot; redraw with: gnuplot THIS_FILE\n";
  script += "set terminal pngcairo size 1200,900 font 'sans,11'\nset output '" + png_path.string() + "'\n";
  std::string xtics;
  for (std::size_t m = 0; m < kModels.size(); ++m)
    xtics += (m == 0 ? "" : ", ") + std::string("'") + kModels[m] + "' " + std::to_string(m + 1);

  // Data blocks: per panel, boxes "x q1 whisker_low whisker_high q3 median colour" and outliers "x value".
  bool any_data[2][2] = {};
  bool any_outliers[2][2] = {};
  for (const bool rotation : {false, true}) {
    for (const bool deskew : {false, true}) {
      const std::string name = std::string(rotation ? "rot" : "trans") + (deskew ? "_deskew" : "_raw");
      std::string boxes = "$" + name + " << EOD\n";
      std::string outliers = "$" + name + "_out << EOD\n";
      for (const CellSummary& cell : cells) {
        if (cell.variant.deskew != deskew) continue;
        std::size_t m = 0;
        while (m < kModels.size() && kModels[m] != cell.variant.model) ++m;
        const std::optional<BoxStats>& stats = panel_stats(cell, rotation);
        if (m == kModels.size() || !stats) continue;
        any_data[rotation][deskew] = true;
        const std::string x = std::to_string(m + 1);
        boxes += x + " " + number(stats->q1) + " " + number(stats->whisker_low) + " " + number(stats->whisker_high) +
                 " " + number(stats->q3) + " " + number(stats->median) + " " + kModelColours[m] + "\n";
        for (const double value : stats->outliers) outliers += x + " " + number(value) + "\n";
        any_outliers[rotation][deskew] = any_outliers[rotation][deskew] || !stats->outliers.empty();
      }
      script += boxes + "EOD\n" + outliers + "EOD\n";
    }
  }

  script += "set multiplot layout 2,2 title 'Final pose error / distance travelled'\n";
  script += "set xrange [0.4:" + std::to_string(kModels.size()) + ".6]\nset xtics (" + xtics + ")\n";
  script += "set grid ytics\nset boxwidth 0.6\nset style fill solid 0.6 border lc rgb 'black'\nunset key\n";
  script += "set yrange [0:*]\nset offsets 0, 0, graph 0.05, 0\n";  // headroom: no outlier on the frame
  for (const bool rotation : {false, true}) {
    for (const bool deskew : {false, true}) {
      const std::string name = std::string(rotation ? "rot" : "trans") + (deskew ? "_deskew" : "_raw");
      script += "set title '" + std::string(deskew ? "de-skew" : "no de-skew") + "'\n";
      script += "set ylabel '" + std::string(rotation ? "rotation error (deg/m)" : "translation error (cm/m)") + "'\n";
      if (!any_data[rotation][deskew]) {
        script +=
            "set label 1 'no data' at graph 0.5, graph 0.5 center\nset yrange [0:1]\nplot 1/0\n"
            "unset label 1\nset yrange [0:*]\n";
        continue;
      }
      script += "plot $" + name + " using 1:2:3:4:5:7 with candlesticks whiskerbars 0.5 lc rgb variable, \\\n     $" +
                name + " using 1:6:6:6:6 with candlesticks lc rgb 'black' lw 2";
      if (any_outliers[rotation][deskew])
        script += ", \\\n     $" + name + "_out using 1:2 with points pt 6 ps 0.8 lc rgb 'black'";
      script += "\n";
    }
  }
  script += "unset multiplot\n";
  return script;
}

std::string draw_box_plot(const std::vector<CellSummary>& cells, const std::filesystem::path& script_path,
                          const std::filesystem::path& png_path) {
  return run_gnuplot(box_plot_script(cells, png_path), script_path);
}

}  // namespace tumble::eval
