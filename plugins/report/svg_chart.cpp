#include "svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace mlod::report {

namespace {

constexpr const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                    "#9467bd", "#8c564b", "#17becf", "#7f7f7f"};
constexpr int kColourCount = static_cast<int>(sizeof(kColours) / sizeof(kColours[0]));

const char* colour(std::size_t series) {
  return kColours[series % kColourCount];
}

std::string num(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f", x);
  return buffer;
}

// A tick label: few digits, no trailing zeros.
std::string label(double x) {
  if (std::fabs(x) < 1e-12)
    return "0";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", x);
  return buffer;
}

// Round tick step (1, 2 or 5 x 10^k) for about `ticks` ticks over `range`.
double niceStep(double range, int ticks) {
  if (!(range > 0.0) || !std::isfinite(range))
    return 1.0;
  const double raw = range / ticks;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (raw <= m * magnitude)
      return m * magnitude;
  return 10.0 * magnitude;
}

struct Axis {
  double min = 0.0;
  double max = 1.0;
  double step = 1.0;
};

// An axis from 0 (or the data's minimum when negative) to a round value above the data.
Axis axisFor(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    lo = 0.0;
    hi = 1.0;
  }
  lo = std::min(lo, 0.0);
  if (hi <= lo)
    hi = lo + 1.0;
  Axis axis;
  axis.step = niceStep(hi - lo, 5);
  axis.min = std::floor(lo / axis.step) * axis.step;
  axis.max = std::ceil(hi / axis.step) * axis.step;
  if (axis.max <= axis.min)
    axis.max = axis.min + axis.step;
  return axis;
}

std::string svgOpen(int width, int height, const std::string& title) {
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"chart\" width=\"" + std::to_string(width) + "\" height=\"" +
         std::to_string(height) + "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) +
         "\" role=\"img\" aria-label=\"" + escapeXml(title) +
         "\" font-family=\"sans-serif\" font-size=\"11\">\n<title>" + escapeXml(title) + "</title>\n<text x=\"" +
         std::to_string(width / 2) + "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\" font-weight=\"bold\">" +
         escapeXml(title) + "</text>\n";
}

std::string legend(const std::vector<std::string>& names, double x, double y) {
  std::string out;
  for (std::size_t s = 0; s < names.size(); ++s) {
    const double row = y + 16.0 * double(s);
    out += "<rect x=\"" + num(x) + "\" y=\"" + num(row - 9) + "\" width=\"10\" height=\"10\" fill=\"" + colour(s) +
           "\"/><text x=\"" + num(x + 14) + "\" y=\"" + num(row) + "\">" + escapeXml(names[s]) + "</text>\n";
  }
  return out;
}

} // namespace

std::string escapeXml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
    case '&':
      out += "&amp;";
      break;
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&#39;";
      break;
    default:
      out += c;
    }
  }
  return out;
}

std::string lineChart(const std::string& title, const std::string& xLabel, const std::string& yLabel,
                      const std::vector<LineSeries>& series) {
  constexpr int width = 560, height = 300;
  constexpr double left = 60, right = 150, top = 30, bottom = 45;
  const double plotW = width - left - right, plotH = height - top - bottom;
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const LineSeries& s : series)
    for (const auto& [x, y] : s.points)
      if (std::isfinite(x) && std::isfinite(y)) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  const Axis ax = axisFor(x0, x1), ay = axisFor(y0, y1);
  const auto px = [&](double x) { return left + (x - ax.min) / (ax.max - ax.min) * plotW; };
  const auto py = [&](double y) { return top + plotH - (y - ay.min) / (ay.max - ay.min) * plotH; };

  std::string out = svgOpen(width, height, title);
  out += "<g stroke=\"#ddd\">\n";
  for (double y = ay.min; y <= ay.max + ay.step * 1e-9; y += ay.step)
    out += "<line x1=\"" + num(left) + "\" y1=\"" + num(py(y)) + "\" x2=\"" + num(left + plotW) + "\" y2=\"" +
           num(py(y)) + "\"/>\n";
  out += "</g>\n<g text-anchor=\"end\">\n";
  for (double y = ay.min; y <= ay.max + ay.step * 1e-9; y += ay.step)
    out += "<text x=\"" + num(left - 5) + "\" y=\"" + num(py(y) + 4) + "\">" + label(y) + "</text>\n";
  out += "</g>\n<g text-anchor=\"middle\">\n";
  for (double x = ax.min; x <= ax.max + ax.step * 1e-9; x += ax.step)
    out += "<text x=\"" + num(px(x)) + "\" y=\"" + num(top + plotH + 15) + "\">" + label(x) + "</text>\n";
  out += "</g>\n<rect x=\"" + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(plotW) + "\" height=\"" +
         num(plotH) + "\" fill=\"none\" stroke=\"#333\"/>\n";
  out += "<text x=\"" + num(left + plotW / 2) + "\" y=\"" + num(height - 8.0) + "\" text-anchor=\"middle\">" +
         escapeXml(xLabel) + "</text>\n";
  out += "<text transform=\"translate(14 " + num(top + plotH / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
         escapeXml(yLabel) + "</text>\n";
  std::vector<std::string> names;
  for (std::size_t s = 0; s < series.size(); ++s) {
    names.push_back(series[s].name);
    std::string points;
    std::string marks;
    for (const auto& [x, y] : series[s].points) {
      if (!std::isfinite(x) || !std::isfinite(y))
        continue;
      points += num(px(x)) + "," + num(py(y)) + " ";
      marks += "<circle cx=\"" + num(px(x)) + "\" cy=\"" + num(py(y)) + "\" r=\"3\"><title>" +
               escapeXml(series[s].name) + ": " + label(x) + ", " + label(y) + "</title></circle>";
    }
    out += "<g class=\"series\" fill=\"" + std::string(colour(s)) + "\"><polyline fill=\"none\" stroke=\"" + colour(s) +
           "\" stroke-width=\"2\" points=\"" + points + "\"/>" + marks + "</g>\n";
  }
  out += legend(names, left + plotW + 12, top + 10);
  out += "</svg>\n";
  return out;
}

std::string barChart(const std::string& title, const std::string& valueLabel,
                     const std::vector<std::string>& categories, const std::vector<std::string>& seriesNames,
                     const std::vector<std::vector<double>>& values) {
  const std::size_t groups = categories.size();
  const std::size_t bars = std::max<std::size_t>(1, seriesNames.size());
  const double barH = 5.0, gap = 6.0;
  const double groupH = barH * double(bars) + gap;
  constexpr double left = 130, right = 150, top = 30, bottom = 40;
  constexpr int width = 640;
  const double plotW = width - left - right;
  const double plotH = std::max(groupH * double(groups), 20.0);
  const int height = static_cast<int>(top + plotH + bottom);
  double hi = 0.0;
  for (const std::vector<double>& row : values)
    for (double v : row)
      if (std::isfinite(v))
        hi = std::max(hi, v);
  const Axis ax = axisFor(0.0, hi);
  const auto px = [&](double x) { return left + (x - ax.min) / (ax.max - ax.min) * plotW; };

  std::string out = svgOpen(width, height, title);
  out += "<g stroke=\"#ddd\">\n";
  for (double x = ax.min; x <= ax.max + ax.step * 1e-9; x += ax.step)
    out += "<line x1=\"" + num(px(x)) + "\" y1=\"" + num(top) + "\" x2=\"" + num(px(x)) + "\" y2=\"" +
           num(top + plotH) + "\"/>\n";
  out += "</g>\n<g text-anchor=\"middle\">\n";
  for (double x = ax.min; x <= ax.max + ax.step * 1e-9; x += ax.step)
    out += "<text x=\"" + num(px(x)) + "\" y=\"" + num(top + plotH + 15) + "\">" + label(x) + "</text>\n";
  out += "</g>\n<text x=\"" + num(left + plotW / 2) + "\" y=\"" + num(height - 8.0) + "\" text-anchor=\"middle\">" +
         escapeXml(valueLabel) + "</text>\n<g text-anchor=\"end\">\n";
  for (std::size_t c = 0; c < groups; ++c)
    out += "<text x=\"" + num(left - 5) + "\" y=\"" + num(top + groupH * double(c) + groupH / 2 + 4) + "\">" +
           escapeXml(categories[c]) + "</text>\n";
  out += "</g>\n";
  for (std::size_t s = 0; s < values.size(); ++s) {
    out += "<g class=\"series\" fill=\"" + std::string(colour(s)) + "\">";
    for (std::size_t c = 0; c < groups && c < values[s].size(); ++c) {
      const double v = std::isfinite(values[s][c]) ? std::max(values[s][c], 0.0) : 0.0;
      out += "<rect x=\"" + num(left) + "\" y=\"" + num(top + groupH * double(c) + gap / 2 + barH * double(s)) +
             "\" width=\"" + num(px(v) - left) + "\" height=\"" + num(barH) + "\"><title>" + escapeXml(categories[c]) +
             ", " + escapeXml(s < seriesNames.size() ? seriesNames[s] : std::string()) + ": " + label(v) +
             "</title></rect>";
    }
    out += "</g>\n";
  }
  out += "<rect x=\"" + num(left) + "\" y=\"" + num(top) + "\" width=\"" + num(plotW) + "\" height=\"" + num(plotH) +
         "\" fill=\"none\" stroke=\"#333\"/>\n";
  out += legend(seriesNames, left + plotW + 12, top + 10);
  out += "</svg>\n";
  return out;
}

} // namespace mlod::report
