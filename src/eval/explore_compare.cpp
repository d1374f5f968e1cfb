// Run-by-run comparison of two sets of seeded exploration runs (explore_compare.hpp).
#include "squint/eval/explore_compare.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <regex>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "squint/core/error.hpp"
#include "squint/io/csv.hpp"

namespace squint::eval {
namespace {

namespace fs = std::filesystem;

int WholeCell(const io::CsvTable& t, std::size_t row, std::size_t col) {
  const double v = t.RequireNumber(row, col);
  if (v < 0.0 || v != std::floor(v) || v > 1e9) {
    throw Error(fmt::format("{}: line {}: column '{}': '{}' is not a whole number >= 0", t.Path().string(),
                            t.LineOf(row), t.Header()[col], t.Cell(row, col)));
  }
  return static_cast<int>(v);
}

void ReadRunsCsv(const fs::path& file, const std::string& set, std::vector<ExploreRunRow>& out) {
  const io::CsvTable t = io::CsvTable::Read(file);
  const std::size_t world = t.Require("world"), start = t.Require("start"), x = t.Require("x_m"),
                    y = t.Require("y_m"), yaw = t.Require("yaw_deg"), distance = t.Require("distance_m"),
                    coverage = t.Require("coverage"), collisions = t.Require("collisions");
  const auto first_hit = t.Find("first_hit");
  const auto first_s = t.Find("first_collision_s");
  for (std::size_t r = 0; r < t.Rows(); ++r) {
    ExploreRunRow row;
    row.set = set;
    row.source = fmt::format("{}:{}", file.string(), t.LineOf(r));
    row.world = t.Cell(r, world);
    if (row.world.empty()) throw Error(row.source + ": column 'world' is empty");
    row.start = WholeCell(t, r, start);
    row.x_m = t.RequireNumber(r, x);
    row.y_m = t.RequireNumber(r, y);
    row.yaw_deg = t.RequireNumber(r, yaw);
    row.distance_m = t.RequireNumber(r, distance);
    row.coverage = t.RequireNumber(r, coverage);
    if (row.coverage < 0.0 || row.coverage > 1.0) {
      throw Error(fmt::format("{}: column 'coverage': {} is outside [0, 1]", row.source, t.Cell(r, coverage)));
    }
    row.collisions = WholeCell(t, r, collisions);
    if (first_hit) row.first_hit = t.Cell(r, *first_hit);
    if (first_s) {
      if (auto s = t.Number(r, *first_s)) row.first_collision_s = *s;
    }
    for (std::size_t c = 0; c < t.Header().size(); ++c) row.cells[t.Header()[c]] = t.Cell(r, c);
    out.push_back(std::move(row));
  }
}

// S of a seed-S folder's name; none for any other name.
std::optional<long long> SeedOf(const std::string& name) {
  static const std::regex kSeed("seed-([0-9]{1,15})");
  std::smatch m;
  if (std::regex_match(name, m, kSeed)) return std::stoll(m[1].str());
  return std::nullopt;
}

// seed-S folders sort by S, then anything else by name.
std::tuple<long long, std::string> SetOrder(const std::string& set) { return {SeedOf(set).value_or(-1), set}; }

using Key = std::tuple<std::string, std::string, int>;  // set, world, start
Key KeyOf(const ExploreRunRow& r) { return {r.set, r.world, r.start}; }

bool KeyLess(const ExploreRunRow& a, const ExploreRunRow& b) {
  return std::make_tuple(SetOrder(a.set), a.world, a.start) < std::make_tuple(SetOrder(b.set), b.world, b.start);
}

std::string RunName(const ExploreRunRow& r) {
  return (r.set.empty() ? std::string() : r.set + " ") + r.world + " start " + std::to_string(r.start);
}

void Accumulate(ExploreGroupComparison& g, const ExploreRunRow& b, const ExploreRunRow& n, bool changed) {
  ++g.runs;
  g.changed += changed ? 1 : 0;
  g.base_coverage += b.coverage;
  g.new_coverage += n.coverage;
  g.base_distance_m += b.distance_m;
  g.new_distance_m += n.distance_m;
  g.base_failed += b.collisions > 0 ? 1 : 0;
  g.new_failed += n.collisions > 0 ? 1 : 0;
}

void Finish(ExploreGroupComparison& g) {
  if (g.runs == 0) return;
  g.base_coverage /= g.runs;
  g.new_coverage /= g.runs;
  g.base_distance_m /= g.runs;
  g.new_distance_m /= g.runs;
}

bool Changed(const ExploreRunRow& b, const ExploreRunRow& n) {
  for (const auto& [name, cell] : b.cells) {
    auto it = n.cells.find(name);
    if (it != n.cells.end() && it->second != cell) return true;
  }
  return false;
}

std::string Contact(const ExploreRunRow& r) {
  std::string s = std::to_string(r.collisions) + (r.collisions == 1 ? " step" : " steps") + " in contact";
  if (std::isfinite(r.first_collision_s)) s += fmt::format(", first at {:.1f} s", r.first_collision_s);
  if (!r.first_hit.empty()) s += ", met " + r.first_hit;
  return s;
}

}  // namespace

std::vector<ExploreRunRow> LoadExploreRuns(const fs::path& path) {
  std::vector<ExploreRunRow> rows;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    ReadRunsCsv(path, "", rows);
  } else if (fs::is_directory(path, ec)) {
    if (fs::exists(path / "runs.csv", ec)) {
      ReadRunsCsv(path / "runs.csv", "", rows);
    } else {
      std::vector<std::string> sets;
      for (const auto& e : fs::directory_iterator(path, ec)) {
        const std::string name = e.path().filename().string();
        if (e.is_directory() && SeedOf(name)) sets.push_back(name);
      }
      if (ec) throw Error(path.string() + ": cannot list the folder: " + ec.message());
      if (sets.empty()) throw Error(path.string() + ": no runs.csv and no seed-S folders in this folder");
      std::sort(sets.begin(), sets.end(), [](const std::string& a, const std::string& b) { return SetOrder(a) < SetOrder(b); });
      for (const std::string& s : sets) {
        if (!fs::is_regular_file(path / s / "runs.csv", ec)) throw Error((path / s).string() + ": no runs.csv in this folder");
        ReadRunsCsv(path / s / "runs.csv", s, rows);
      }
    }
  } else {
    throw Error(path.string() + ": no such file or folder");
  }
  if (rows.empty()) throw Error(path.string() + ": no runs (runs.csv holds only its header)");
  std::map<Key, const ExploreRunRow*> seen;
  for (const ExploreRunRow& r : rows) {
    auto [it, fresh] = seen.emplace(KeyOf(r), &r);
    if (!fresh) throw Error(r.source + ": " + RunName(r) + " appears twice (first at " + it->second->source + ")");
  }
  return rows;
}

double SignTestP(int a, int b) {
  SQUINT_ENSURE(a >= 0 && b >= 0, "counts must be >= 0");
  const int n = a + b;
  if (n == 0) return 1.0;
  const int k = std::min(a, b);
  // P(X <= k) for X ~ Binomial(n, 1/2), doubled (the distribution is symmetric), at most 1.
  double tail = 0.0;
  for (int i = 0; i <= k; ++i) {
    tail += std::exp(std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) - n * std::log(2.0));
  }
  return std::min(1.0, 2.0 * tail);
}

ExploreComparison CompareExploreRuns(const std::vector<ExploreRunRow>& base, const std::vector<ExploreRunRow>& next) {
  std::map<Key, const ExploreRunRow*> by_key;
  for (const ExploreRunRow& r : next) by_key.emplace(KeyOf(r), &r);
  std::vector<std::pair<const ExploreRunRow*, const ExploreRunRow*>> pairs;
  std::set<Key> matched;
  ExploreComparison c;
  for (const ExploreRunRow& b : base) {
    auto it = by_key.find(KeyOf(b));
    if (it == by_key.end()) {
      ++c.only_in_base;
      continue;
    }
    const ExploreRunRow& n = *it->second;
    const double dyaw = std::remainder(b.yaw_deg - n.yaw_deg, 360.0);
    if (std::abs(b.x_m - n.x_m) > 1e-3 || std::abs(b.y_m - n.y_m) > 1e-3 || std::abs(dyaw) > 0.01) {
      throw Error(fmt::format("{} starts at ({:.3f}, {:.3f}, {:.2f} deg) in {} but at ({:.3f}, {:.3f}, {:.2f} deg) in {}: "
                              "not the same starts (another world file, --starts or --seed?)",
                              RunName(b), b.x_m, b.y_m, b.yaw_deg, b.source, n.x_m, n.y_m, n.yaw_deg, n.source));
    }
    pairs.emplace_back(&b, &n);
    matched.insert(KeyOf(b));
  }
  c.only_in_new = static_cast<int>(next.size() - matched.size());
  if (pairs.empty()) throw Error("the two sets share no run (runs are matched by seed-S folder, world and start)");
  std::sort(pairs.begin(), pairs.end(), [](const auto& p, const auto& q) { return KeyLess(*p.first, *q.first); });

  std::map<std::string, ExploreGroupComparison> worlds;
  c.all.world = "all";
  double sum = 0.0, sum2 = 0.0;
  for (const auto& [b, n] : pairs) {
    const bool changed = Changed(*b, *n);
    ExploreGroupComparison& g = worlds[b->world];
    g.world = b->world;
    Accumulate(g, *b, *n, changed);
    Accumulate(c.all, *b, *n, changed);
    const double d = n->coverage - b->coverage;
    sum += d;
    sum2 += d * d;
    if (b->collisions == 0 && n->collisions > 0) c.newly_failed.emplace_back(*b, *n);
    if (b->collisions > 0 && n->collisions == 0) c.cleared.emplace_back(*b, *n);
  }
  for (auto& [name, g] : worlds) {
    Finish(g);
    c.worlds.push_back(g);
  }
  Finish(c.all);
  const double count = static_cast<double>(pairs.size());
  c.coverage_diff_mean = sum / count;
  if (pairs.size() >= 2) {
    const double var = std::max(0.0, (sum2 - sum * sum / count) / (count - 1.0));
    c.coverage_diff_ci95 = 1.96 * std::sqrt(var / count);
  }
  c.failure_sign_p = SignTestP(static_cast<int>(c.newly_failed.size()), static_cast<int>(c.cleared.size()));
  return c;
}

std::string FormatExploreComparison(const ExploreComparison& c, const std::string& base_label,
                                    const std::string& new_label) {
  std::string s = fmt::format("Runs compared: {} ({} changed); left out, in one set only: {} in BASE, {} in NEW.\n",
                              c.all.runs, c.all.changed, c.only_in_base, c.only_in_new);
  s += fmt::format("BASE: {}\nNEW: {}\n\n", base_label, new_label);
  s += "| world | runs | changed | coverage BASE | coverage NEW | distance m BASE | distance m NEW | with collision BASE | with collision NEW |\n"
       "| --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  auto line = [&](const ExploreGroupComparison& g) {
    s += fmt::format("| {} | {} | {} | {:.4f} | {:.4f} | {:.1f} | {:.1f} | {} | {} |\n", g.world, g.runs, g.changed,
                     g.base_coverage, g.new_coverage, g.base_distance_m, g.new_distance_m, g.base_failed, g.new_failed);
  };
  for (const ExploreGroupComparison& g : c.worlds) line(g);
  line(c.all);
  s += "\n";
  if (std::isfinite(c.coverage_diff_ci95)) {
    s += fmt::format("Coverage, NEW - BASE, paired: {:+.4f} +- {:.4f} (95 % interval of the mean)\n", c.coverage_diff_mean,
                     c.coverage_diff_ci95);
  } else {
    s += fmt::format("Coverage, NEW - BASE: {:+.4f} (one run: no interval)\n", c.coverage_diff_mean);
  }
  s += fmt::format(
      "Runs with a collision: {} in NEW against {} in BASE; {} only in NEW, {} only in BASE "
      "(two-sided sign test on those {}: p = {:.3g})\n",
      c.all.new_failed, c.all.base_failed, c.newly_failed.size(), c.cleared.size(),
      c.newly_failed.size() + c.cleared.size(), c.failure_sign_p);
  if (!c.newly_failed.empty()) {
    s += "\nWith a collision in NEW only:\n";
    for (const auto& [b, n] : c.newly_failed) s += "- " + RunName(n) + ": " + Contact(n) + "\n";
  }
  if (!c.cleared.empty()) {
    s += "\nWith a collision in BASE only:\n";
    for (const auto& [b, n] : c.cleared) s += "- " + RunName(b) + ": " + Contact(b) + "\n";
  }
  return s;
}

}  // namespace squint::eval
