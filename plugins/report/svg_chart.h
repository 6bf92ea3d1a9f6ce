#pragma once
// Small inline-SVG charts for the HTML report: no script, no external resource, text
// escaped. Sizes in SVG user units (pixels at 100% zoom).

#include <string>
#include <utility>
#include <vector>

namespace mlod::report {

struct LineSeries {
  std::string name;
  std::vector<std::pair<double, double>> points; // (x, y), drawn in order; non-finite points are skipped
};

// A line chart with points marked, axes with round ticks and a legend. Empty series give an
// empty plot with its axes.
std::string lineChart(const std::string& title, const std::string& xLabel, const std::string& yLabel,
                      const std::vector<LineSeries>& series);

// Horizontal grouped bars: one row per category, one bar per series in it.
// values[s][c] is series s at category c.
std::string barChart(const std::string& title, const std::string& valueLabel,
                     const std::vector<std::string>& categories, const std::vector<std::string>& seriesNames,
                     const std::vector<std::vector<double>>& values);

// `text` with &, <, >, " and ' escaped for HTML and SVG.
std::string escapeXml(const std::string& text);

} // namespace mlod::report
