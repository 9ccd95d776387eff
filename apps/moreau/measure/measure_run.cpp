#include "measure/measure_run.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <numeric>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"
#include "moreau/io/text_trajectory.h"
#include "output.h"

namespace moreau::cli {
namespace {

using crowds::Point;
using crowds::Polygon;

// "NAME=a,b,c": the name and the numbers; InputError("FLAG", …) for anything else.
std::pair<std::string, std::vector<double>> SplitMeasureSpec(const std::string& flag,
                                                             const std::string& spec) {
  const std::size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError(flag, fmt::format("expected NAME=numbers (got \"{}\")", spec));
  }
  std::string name = spec.substr(0, eq);
  for (const char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) {
      throw InputError(flag, fmt::format("a name is letters, digits, _ and - (got \"{}\")", name));
    }
  }
  std::vector<double> numbers;
  std::string_view rest = std::string_view(spec).substr(eq + 1);
  while (true) {
    const std::size_t comma = std::min(rest.find(','), rest.size());
    const std::string_view word = rest.substr(0, comma);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
    if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(v)) {
      throw InputError(flag, fmt::format("\"{}\" is not a finite number ({})", word, name));
    }
    numbers.push_back(v);
    if (comma == rest.size()) break;
    rest.remove_prefix(comma + 1);
  }
  return {std::move(name), std::move(numbers)};
}

Polygon MeasurePolygon(const std::string& flag, const std::string& name,
                       const std::vector<double>& v) {
  Polygon p;
  if (v.size() == 4) {
    if (!(v[2] > v[0] && v[3] > v[1])) {
      throw InputError(flag,
                       fmt::format("{}: a rectangle x0,y0,x1,y1 needs x1 > x0, y1 > y0", name));
    }
    p = crowds::Rectangle({v[0], v[1]}, {v[2], v[3]});
  } else if (v.size() >= 6 && v.size() % 2 == 0) {
    for (std::size_t k = 0; k < v.size(); k += 2) p.push_back({v[k], v[k + 1]});
  } else {
    throw InputError(flag, fmt::format("{}: give x0,y0,x1,y1 (a rectangle) or three or more "
                                       "vertices x,y (got {} numbers)",
                                       name, v.size()));
  }
  if (!(crowds::PolygonArea(p) > 0.0)) {
    throw InputError(flag, fmt::format("{}: the polygon has no area", name));
  }
  return p;
}

// One person's rows, in frame order.
struct MeasureTrack {
  std::vector<std::size_t> rows;
  std::vector<double> t;
  std::vector<Point> x;
};

// The tracks (rows by id, then frame) and each row's speed; InputError for an id twice in a frame.
std::vector<MeasureTrack> MeasureTracks(const io::TextTrajectory& traj, const std::string& path,
                                        std::vector<double>& speed) {
  std::vector<std::size_t> order(traj.rows());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(traj.id[a], traj.frame[a]) < std::tie(traj.id[b], traj.frame[b]);
  });
  std::vector<MeasureTrack> tracks;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t r = order[k];
    if (k == 0 || traj.id[r] != traj.id[order[k - 1]]) {
      tracks.emplace_back();
    } else if (traj.frame[r] == traj.frame[order[k - 1]]) {
      throw InputError(
          fmt::format("{}: person {} appears twice in frame {}", path, traj.id[r], traj.frame[r]));
    }
    tracks.back().rows.push_back(r);
    tracks.back().t.push_back(static_cast<double>(traj.frame[r]) / traj.frame_rate);
    tracks.back().x.push_back({traj.x[r], traj.y[r]});
  }
  speed.assign(traj.rows(), 0.0);
  for (const MeasureTrack& track : tracks) {
    const std::vector<Point> v = crowds::TrackVelocities(track.t, track.x);
    for (std::size_t k = 0; k < v.size(); ++k) speed[track.rows[k]] = std::hypot(v[k][0], v[k][1]);
  }
  return tracks;
}

Polygon MeasureDefaultBound(const io::TextTrajectory& traj) {
  const auto [xlo, xhi] = std::minmax_element(traj.x.begin(), traj.x.end());
  const auto [ylo, yhi] = std::minmax_element(traj.y.begin(), traj.y.end());
  return crowds::Rectangle({*xlo - 1.0, *ylo - 1.0}, {*xhi + 1.0, *yhi + 1.0});
}

nlohmann::json MeasurePolygonJson(const Polygon& p) {
  nlohmann::json j = nlohmann::json::array();
  for (const Point& v : p) j.push_back({v[0], v[1]});
  return j;
}

std::string MeasureNumber(double v) { return fmt::format("{:.12g}", v); }

struct MeasureAreaTotals {
  double classic = 0.0, voronoi = 0.0, speed = 0.0;
};

// Each line's first crossings per person, sorted by time; their rows go to crossings_csv.
std::vector<std::vector<double>> MeasureCrossings(const MeasureSettings& settings,
                                                  const io::TextTrajectory& traj,
                                                  const std::vector<MeasureTrack>& tracks,
                                                  std::string& crossings_csv) {
  std::vector<std::vector<double>> times(settings.lines.size());
  for (std::size_t l = 0; l < settings.lines.size(); ++l) {
    std::vector<std::pair<double, std::int64_t>> crossed;
    for (const MeasureTrack& track : tracks) {
      if (const auto t = crowds::FirstCrossingTime(settings.lines[l].line, track.t, track.x)) {
        crossed.emplace_back(*t, traj.id[track.rows.front()]);
      }
    }
    std::sort(crossed.begin(), crossed.end());
    for (const auto& [t, id] : crossed) {
      crossings_csv += fmt::format("{},{},{}\n", settings.lines[l].name, id, MeasureNumber(t));
      times[l].push_back(t);
    }
  }
  return times;
}

// Per frame: the people present, their cells, each area's row and each line's cumulative count.
// Returns the number of frames; adds each area's measurements to totals.
std::size_t MeasureFrames(const MeasureSettings& settings, const io::TextTrajectory& traj,
                          const std::vector<double>& speed, const crowds::VoronoiOptions& voronoi,
                          const std::vector<std::vector<double>>& crossing_times,
                          std::vector<MeasureAreaTotals>& totals, std::string& csv) {
  std::vector<std::size_t> by_frame(traj.rows());
  std::iota(by_frame.begin(), by_frame.end(), std::size_t{0});
  std::stable_sort(by_frame.begin(), by_frame.end(),
                   [&](std::size_t a, std::size_t b) { return traj.frame[a] < traj.frame[b]; });
  std::size_t frames = 0;
  std::vector<Point> points;
  std::vector<double> speeds;
  for (std::size_t begin = 0; begin < by_frame.size(); ++frames) {
    const std::int64_t frame = traj.frame[by_frame[begin]];
    points.clear();
    speeds.clear();
    for (; begin < by_frame.size() && traj.frame[by_frame[begin]] == frame; ++begin) {
      points.push_back({traj.x[by_frame[begin]], traj.y[by_frame[begin]]});
      speeds.push_back(speed[by_frame[begin]]);
    }
    const double t = static_cast<double>(frame) / traj.frame_rate;
    std::vector<Polygon> cells;
    if (!settings.areas.empty()) cells = crowds::VoronoiCells(points, voronoi);
    for (std::size_t a = 0; a < settings.areas.size(); ++a) {
      const crowds::AreaMeasurement m =
          crowds::MeasureArea(points, cells, speeds, settings.areas[a].polygon);
      csv += fmt::format("{},{},{},{},{},{},{},\n", frame, MeasureNumber(t), settings.areas[a].name,
                         m.count, MeasureNumber(m.density_classic),
                         MeasureNumber(m.density_voronoi), MeasureNumber(m.speed_voronoi));
      totals[a].classic += m.density_classic;
      totals[a].voronoi += m.density_voronoi;
      totals[a].speed += m.speed_voronoi;
    }
    for (std::size_t l = 0; l < settings.lines.size(); ++l) {
      const auto n = std::count_if(crossing_times[l].begin(), crossing_times[l].end(),
                                   [&](double c) { return c <= t; });
      csv += fmt::format("{},{},{},,,,,{}\n", frame, MeasureNumber(t), settings.lines[l].name, n);
    }
  }
  return frames;
}

// The areas' means and the lines' flows: summary.json's "areas" and "lines", and printed lines.
std::string MeasureResults(const MeasureSettings& settings, std::size_t frames,
                           const std::vector<MeasureAreaTotals>& totals,
                           const std::vector<std::vector<double>>& crossing_times,
                           nlohmann::json& summary) {
  std::string report;
  summary["areas"] = nlohmann::json::array();
  summary["lines"] = nlohmann::json::array();
  const double f = static_cast<double>(std::max<std::size_t>(frames, 1));
  for (std::size_t a = 0; a < settings.areas.size(); ++a) {
    const NamedArea& area = settings.areas[a];
    summary["areas"].push_back({{"name", area.name},
                                {"polygon", MeasurePolygonJson(area.polygon)},
                                {"area", crowds::PolygonArea(area.polygon)},
                                {"mean_density_classic", totals[a].classic / f},
                                {"mean_density_voronoi", totals[a].voronoi / f},
                                {"mean_speed_voronoi", totals[a].speed / f}});
    report += fmt::format(
        "area {}: mean over {} frames: density {:.4g} /m² (classic), {:.4g} "
        "/m² (Voronoi), speed {:.4g} m/s (Voronoi)\n",
        area.name, frames, totals[a].classic / f, totals[a].voronoi / f, totals[a].speed / f);
  }
  for (std::size_t l = 0; l < settings.lines.size(); ++l) {
    const NamedLine& line = settings.lines[l];
    const crowds::LineFlow flow = crowds::FlowThroughLine(crossing_times[l], line.line.length());
    summary["lines"].push_back({{"name", line.name},
                                {"a", {line.line.a[0], line.line.a[1]}},
                                {"b", {line.line.b[0], line.line.b[1]}},
                                {"length", line.line.length()},
                                {"crossings", flow.crossings},
                                {"first", flow.first},
                                {"last", flow.last},
                                {"flow", flow.flow},
                                {"specific_flow", flow.specific_flow}});
    report += fmt::format(
        "line {}: {} crossings from t = {:.4g} s to {:.4g} s: flow {:.4g} /s, "
        "{:.4g} /(m s)\n",
        line.name, flow.crossings, flow.first, flow.last, flow.flow, flow.specific_flow);
  }
  return report;
}

}  // namespace

NamedArea ParseArea(const std::string& spec) {
  auto [name, v] = SplitMeasureSpec("--area", spec);
  Polygon p = MeasurePolygon("--area", name, v);
  return {std::move(name), std::move(p)};
}

NamedLine ParseLine(const std::string& spec) {
  auto [name, v] = SplitMeasureSpec("--line", spec);
  if (v.size() != 4) {
    throw InputError("--line",
                     fmt::format("{}: give ax,ay,bx,by (got {} numbers)", name, v.size()));
  }
  const crowds::MeasurementLine line{{v[0], v[1]}, {v[2], v[3]}};
  if (!(line.length() > 0.0)) throw InputError("--line", name + ": a and b must differ");
  return {std::move(name), line};
}

Polygon ParseBound(const std::string& spec) {
  Polygon p =
      MeasurePolygon("--bound", "bound", SplitMeasureSpec("--bound", "bound=" + spec).second);
  if (!crowds::IsConvex(p)) throw InputError("--bound", "must be a convex polygon");
  return p;
}

std::string RunMeasure(const MeasureSettings& settings) {
  if (settings.areas.empty() && settings.lines.empty()) {
    throw InputError("give at least one --area or --line");
  }
  const io::TextTrajectory traj = io::ReadTextTrajectory(settings.trajectory, settings.frame_rate);
  crowds::VoronoiOptions voronoi;
  voronoi.bound = settings.bound.value_or(MeasureDefaultBound(traj));
  voronoi.cutoff_radius = settings.cutoff_radius;
  voronoi.cutoff_vertices = settings.cutoff_vertices;
  try {
    voronoi.Validate();
  } catch (const InputError& e) {  // the options' keys as the flags that set them
    const std::string flag = e.key() == "cutoff_radius"     ? "--cutoff"
                             : e.key() == "cutoff_vertices" ? "--cutoff-vertices"
                                                            : "--bound";
    throw InputError(flag, e.reason());
  }
  std::vector<double> speed;
  const std::vector<MeasureTrack> tracks = MeasureTracks(traj, settings.trajectory, speed);
  std::string crossings_csv = "line,id,t\n";
  const auto crossing_times = MeasureCrossings(settings, traj, tracks, crossings_csv);
  std::string csv = "frame,t,name,count,density_classic,density_voronoi,speed_voronoi,crossings\n";
  std::vector<MeasureAreaTotals> totals(settings.areas.size());
  const std::size_t frames =
      MeasureFrames(settings, traj, speed, voronoi, crossing_times, totals, csv);
  nlohmann::json summary = {
      {"trajectory", settings.trajectory},
      {"frame_rate", traj.frame_rate},
      {"frames", frames},
      {"people", tracks.size()},
      {"bound", MeasurePolygonJson(voronoi.bound)},
      {"cutoff_radius",
       settings.cutoff_radius ? nlohmann::json(*settings.cutoff_radius) : nlohmann::json(nullptr)},
      {"cutoff_vertices", settings.cutoff_vertices},
      {"velocity", "central differences over frames, one-sided at a track's ends"}};
  const std::string report = MeasureResults(settings, frames, totals, crossing_times, summary);
  OutputDir out(settings.out);
  out.WriteText("measurements.csv", csv);
  out.WriteText("crossings.csv", crossings_csv);
  out.WriteText("summary.json", JsonText(summary) + "\n");
  out.Commit();
  return report + fmt::format("wrote {}/measurements.csv, crossings.csv, summary.json\n",
                              out.dir().string());
}

}  // namespace moreau::cli
