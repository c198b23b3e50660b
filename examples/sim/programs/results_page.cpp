#include "results_page.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <lieservo_cli/program.hpp>

#include <lieservo_plot/svg_figure.hpp>

namespace lieservo::sim::programs {

void printSummaryTable(const std::vector<Row>& rows) {
  std::printf("\n%-16s %-88s %-24s %-24s %s\n", "task", "quantity", "simulation", "paper", "pass");
  std::printf("%s\n", std::string(162, '-').c_str());
  for (const Row& r : rows)
    std::printf("%-16s %-88s %-24s %-24s %s\n", r.task.c_str(), r.item.c_str(), r.sim.c_str(), r.paper.c_str(),
                r.pass ? "yes" : "NO");
  std::printf("%s\n", std::string(162, '-').c_str());
}

bool writePushingSummaryFigure(const std::string& path, const std::vector<const PushingResult*>& results,
                               const std::vector<std::string>& titles) {
  plot::SvgFigure fig("Final target error (mm), mean ± sd: simulation (filled) beside the paper (open)");
  double x_max = 1.2 * Bounds::pushing_error_max;
  for (const PushingResult* r : results)
    for (const PushingCase& c : r->cases) x_max = std::max(x_max, 1.05 * (c.mean_error + c.sd_error));
  int number = 0;
  for (std::size_t k = 0; k < results.size(); ++k) {
    const auto& cases = results[k]->cases;
    plot::SvgPanel& p = fig.panel(titles[k], "final target error (mm)", "case (numbered in the captions)");
    p.equal_aspect = false;
    const double n = double(cases.size());
    const double top = n + 0.5 + std::max(1.5, 0.2 * n);  // room for the legend above the cases
    p.limits = std::array<double, 4>{0.0, x_max, 0.5, top};
    p.line({{Bounds::pushing_error_max, 0.5}, {Bounds::pushing_error_max, top}}, "#c00000", 1.5, true,
           "criterion: every trial <= 10 mm");
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const PushingCase& c = cases[i];
      const double y = double(i) + 1;  // case i + 1 at height i + 1
      const PaperValue pv = paperValue(c);
      if (std::isfinite(c.mean_error)) {
        p.line({{std::max(0.0, c.mean_error - c.sd_error), y + 0.15}, {c.mean_error + c.sd_error, y + 0.15}},
               "#1f5fbf", 2.0, false, i == 0 ? "simulation" : "");
        p.marker({c.mean_error, y + 0.15}, 0.12, "#1f5fbf", true);
      }
      if (std::isfinite(pv.mean)) {
        p.line({{std::max(0.0, pv.mean - pv.sd), y - 0.15}, {pv.mean + pv.sd, y - 0.15}}, "#e07b00", 2.0, false,
               i == 0 ? "paper" : "");
        p.marker({pv.mean, y - 0.15}, 0.12, "#e07b00", false);
      }
      char b[240];
      std::snprintf(b, sizeof b, "%s %zu: %s, %s%s", titles[k].c_str(), i + 1, displayName(c.setup.object).c_str(),
                    c.setup.surface.name.c_str(), c.judged ? "" : " (reported)");
      fig.caption(b);
      ++number;
    }
  }
  if (number == 0) return true;
  return fig.write(path);
}

namespace {

std::string html(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else out += c;
  }
  return out;
}

// One page of results: the summary table beside the paper's numbers, every figure in the
// results folder (SVG and PNG, its subfolders included) and links to the CSV logs. The
// pictures of a plot `X.svg` (its time-lapses, strips of frames and videos, in the folder `X/`)
// follow it, side by side.
}  // namespace

bool writeIndex(const std::string& dir, const std::string& heading, const std::vector<Row>& rows,
                const std::vector<std::string>& failures) {
  namespace fs = std::filesystem;
  std::vector<std::string> figures, logs, videos;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (!it->is_regular_file(ec)) continue;
    const std::string ext = it->path().extension().string();
    const std::string rel = fs::relative(it->path(), dir, ec).generic_string();
    if (ext == ".svg" || ext == ".png") figures.push_back(rel);
    else if (ext == ".csv") logs.push_back(rel);
    else if (ext == ".mp4" || ext == ".webm") videos.push_back(rel);
  }
  std::sort(figures.begin(), figures.end());
  std::sort(logs.begin(), logs.end());
  std::sort(videos.begin(), videos.end());
  // The folder X/ of a plot X.svg: its pictures.
  auto folderOf = [](const std::string& rel) { return rel.substr(0, rel.find_last_of('/') + 1); };
  auto isPlot = [](const std::string& rel) {
    return rel.size() > 4 && rel.compare(rel.size() - 4, 4, ".svg") == 0 && rel.find('/') == std::string::npos;
  };
  std::vector<std::string> plot_folders;
  for (const auto& x : figures)
    if (isPlot(x)) plot_folders.push_back(x.substr(0, x.size() - 4) + "/");
  auto belongs = [&](const std::string& rel) {
    return std::find(plot_folders.begin(), plot_folders.end(), folderOf(rel)) != plot_folders.end();
  };
  std::ostringstream f;
  f << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>lieservo results</title>\n"
       "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
       "td,th{border:1px solid #ccc;padding:2px 6px}.no{color:#b00;font-weight:bold}"
       "img{max-width:100%;border:1px solid #eee;margin:8px 0}.pictures{display:flex;flex-wrap:wrap;gap:8px}"
       ".pictures figure{margin:0;flex:1 1 45%;max-width:49%}figcaption{font-size:small;color:#555}"
       "</style></head><body>\n"
    << "<h1>lieservo: the paper's four tasks in simulation</h1>\n<pre>" << html(heading) << "</pre>\n"
    << "<h2>Pushing beside the paper</h2>\n<img id=\"summary\" src=\"" << kSummaryFigure
    << "\" alt=\"each pushing case's final target error beside the paper's\">\n"
    << "<h2>Summary beside the paper</h2>\n<table><tr><th>task</th><th>quantity</th><th>simulation</th>"
       "<th>paper</th><th>pass</th></tr>\n";
  for (const Row& r : rows)
    f << "<tr><td>" << html(r.task) << "</td><td>" << html(r.item) << "</td><td>" << html(r.sim) << "</td><td>"
      << html(r.paper) << "</td><td" << (!r.judged ? ">reported" : r.pass ? ">yes" : " class=\"no\">NO")
      << "</td></tr>\n";
  f << "</table>\n";
  if (!failures.empty()) {
    f << "<h2>Failures</h2>\n<ul>\n";
    for (const auto& x : failures) f << "<li>" << html(x) << "</li>\n";
    f << "</ul>\n";
  }
  f << "<h2>Figures</h2>\n";
  for (const auto& x : figures) {
    if (belongs(x) || x == kSummaryFigure) continue;  // shown under its plot, or at the top
    f << "<h3>" << html(x) << "</h3>\n<img src=\"" << html(x) << "\" alt=\"" << html(x) << "\">\n";
    if (!isPlot(x)) continue;
    const std::string folder = x.substr(0, x.size() - 4) + "/";
    bool open = false;
    for (const auto& p : figures)
      if (folderOf(p) == folder) {
        if (!open) f << "<div class=\"pictures\">\n", open = true;
        f << "<figure><img class=\"picture\" src=\"" << html(p) << "\" alt=\"" << html(p) << "\"><figcaption>"
          << html(p) << "</figcaption></figure>\n";
      }
    if (open) f << "</div>\n";
    for (const auto& v : videos)
      if (folderOf(v) == folder) f << "<p>video: <a href=\"" << html(v) << "\">" << html(v) << "</a></p>\n";
  }
  f << "<h2>Logs</h2>\n<ul>\n";
  for (const auto& x : logs) f << "<li><a href=\"" << html(x) << "\">" << html(x) << "</a></li>\n";
  f << "</ul>\n</body></html>\n";
  std::string why;
  return lieservo::cli::writeFileAtomically(dir + "/index.html", f.str(), why);
}


}  // namespace lieservo::sim::programs
