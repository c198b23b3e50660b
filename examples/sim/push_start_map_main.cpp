// lieservo_push_start_map — where single-arm pushing ends, as a map over the object's start
// placement (docs/simulation.md, "Margins").
//
//   lieservo_push_start_map [--max-offset MM] [--offset-step MM] [--max-yaw DEG] [--yaw-step DEG]
//                           [--seed N] [--observations auto|real|gaussian] [--data DIR]
//                           [--model-card FILE] [--out FILE.csv]
//
// The demo places each pushed object by hand, as a person would: offset sideways and turned by
// a seeded draw (normal, sd 2 mm and 2°, clipped at ±4 mm and ±4°; runPushTrial). Here the
// placement is fixed instead, at every point of a grid over that box, with the support's μ_s
// at its nominal value, and the eight single-arm cases of the demo (Tables 7–8, the paper's
// controllers) are pushed once from each. The table says per case how far from the target each
// start ends; the summary says which starts miss (> 10 mm, Bounds::pushing_error_max, or not
// reached) in any case, and how likely the demo's draw is to land on them.
//
// Exit status (lieservo_cli/program.hpp): 0 when the map was made, whatever it shows; 2 on bad
// usage or set-up (--out naming a file that is not such a map among them), with a message
// naming the option or file.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <lieservo_cli/cli.hpp>

#include "lieservo_sim/csv_log.hpp"
#include "lieservo_sim/tasks.hpp"
#include "programs/observation_setup.hpp"

namespace {

using namespace lieservo::sim;
namespace cli = lieservo::cli;

// The demo's placement draw (runPushTrial): each coordinate normal with this sd, clipped at
// kClip sd.
constexpr double kDrawSd = 2.0;  // mm and degrees
constexpr double kClip = 2.0;

// Points from −max to max in steps of `step` (max a whole number of steps).
std::vector<double> gridAxis(double max, double step) {
  std::vector<double> v;
  const int n = int(std::lround(max / step));
  for (int k = -n; k <= n; ++k) v.push_back(k * step);
  return v;
}

// The probability that the demo's draw lands in grid point k's cell: the draw's normal over
// [x − step/2, x + step/2], the end cells open to ±∞ (the clip puts the tails on the edges).
double cellProbability(const std::vector<double>& axis, std::size_t k, double step) {
  auto cdf = [](double x) { return 0.5 * std::erfc(-x / (kDrawSd * std::sqrt(2.0))); };
  const double lo = k == 0 ? 0.0 : cdf(axis[k] - step / 2);
  const double hi = k + 1 == axis.size() ? 1.0 : cdf(axis[k] + step / 2);
  return hi - lo;
}

bool miss(const PushTrial& t) { return !t.terminated || t.target_error > Bounds::pushing_error_max; }

// The push's initial lever arm: how far along the face the contact starts from the foot of the
// perpendicular through the object's centre, d0 = offset − A sin(yaw) for a face A from the
// centre. The model e = g |d0 − d*| fitted by least squares (g in closed form, A and d* on a
// grid), over the starts that reached the target.
struct LeverArmFit {
  double A = 0, d_star = 0, gain = 0, rms = 0;
};
LeverArmFit fitLeverArm(const std::vector<double>& offsets, const std::vector<double>& yaws,
                        const std::vector<std::vector<double>>& error) {
  LeverArmFit best;
  double best_ss = std::numeric_limits<double>::infinity();
  int n = 0;
  for (int ia = 0; ia <= 200; ++ia) {      // A = 0 … 100 mm in 0.5 mm
    for (int id = 0; id <= 200; ++id) {    // d* = −5 … 5 mm in 0.05 mm
      const double A = 0.5 * ia, d_star = -5 + 0.05 * id;
      double xx = 0, xe = 0, ee = 0;
      n = 0;
      for (std::size_t i = 0; i < yaws.size(); ++i)
        for (std::size_t j = 0; j < offsets.size(); ++j) {
          const double e = error[i][j];
          if (std::isnan(e)) continue;
          const double x = std::abs(offsets[j] - A * std::sin(deg2rad(yaws[i])) - d_star);
          xx += x * x, xe += x * e, ee += e * e, ++n;
        }
      if (xx <= 0) continue;
      const double ss = ee - xe * xe / xx;  // residual of the best gain xe / xx
      if (ss < best_ss) best_ss = ss, best = {A, d_star, xe / xx, 0};
    }
  }
  best.rms = n ? std::sqrt(std::max(0.0, best_ss) / n) : 0;
  return best;
}

// The grid and the pushes from each of its points.
struct StartMap {
  double max_offset = 4, offset_step = 1, max_yaw = 4, yaw_step = 1;
  std::vector<double> offsets, yaws;
  std::vector<std::string> names, columns;
  std::vector<ObjectSpec> objects;
  std::vector<std::vector<std::vector<double>>> error;  // [case][yaw][offset], nan: not reached
  std::vector<std::vector<bool>> any_miss;              // [yaw][offset]
};

// The first line of the CSV this program writes (--out): only such a file is overwritten.
constexpr const char* kCsvStart = "offset_mm,yaw_deg,";

// Parses the options: -1 to go on, else the exit status.
int parseOptions(int argc, char** argv, StartMap& m, lieservo::sim::programs::ObservationChoice& obs,
                 TaskOptions& opt, std::string& out_csv) {
  CLI::App app("lieservo_push_start_map: single-arm pushing from fixed start placements (offset x yaw), the\n"
               "paper's controllers, one push per case and point; prints each case's target error over the\n"
               "grid. Exit status: 0 the map was made, 2 bad usage or set-up.",
               "lieservo_push_start_map");
  app.add_option("--max-offset", m.max_offset, "the grid's sideways offsets span +-this (mm)")
      ->capture_default_str()
      ->check(cli::finiteIn(0, 20));
  app.add_option("--offset-step", m.offset_step, "between offsets (mm)")
      ->capture_default_str()
      ->check(cli::finiteIn(0.1, 20));
  app.add_option("--max-yaw", m.max_yaw, "the grid's yaws span +-this (deg)")
      ->capture_default_str()
      ->check(cli::finiteIn(0, 20));
  app.add_option("--yaw-step", m.yaw_step, "between yaws (deg)")->capture_default_str()->check(cli::finiteIn(0.1, 20));
  app.add_option("--seed", opt.seed, "seed of the observations' noise (the gaussian mode)")
      ->capture_default_str()
      ->check(cli::integerIn<std::uint64_t>(0, 1000000000000000));
  lieservo::sim::programs::addObservationOptions(app, obs, false);
  app.add_option("--out", out_csv,
                 "also write the target errors to this CSV file (a row per start, a column per case; an existing "
                 "file only if it is such a map)")
      ->check(cli::nonEmptyPath());
  if (const int status = cli::parse(app, argc, argv); status >= 0) return status;
  if (std::abs(m.max_offset / m.offset_step - std::round(m.max_offset / m.offset_step)) > 1e-9 ||
      std::abs(m.max_yaw / m.yaw_step - std::round(m.max_yaw / m.yaw_step)) > 1e-9) {
    std::fprintf(stderr, "--max-offset and --max-yaw must be whole numbers of their steps\n");
    return cli::kUsageOrSetup;
  }
  m.offsets = gridAxis(m.max_offset, m.offset_step);
  m.yaws = gridAxis(m.max_yaw, m.yaw_step);
  return -1;
}

// Pushes the eight cases once from each grid point: false when the real observations failed.
bool pushFromEveryStart(StartMap& m, TaskOptions& opt) {
  m.any_miss.assign(m.yaws.size(), std::vector<bool>(m.offsets.size(), false));
  for (std::size_t i = 0; i < m.yaws.size(); ++i) {
    for (std::size_t j = 0; j < m.offsets.size(); ++j) {
      opt.start_offset = m.offsets[j];
      opt.start_yaw = deg2rad(m.yaws[i]);
      const PushingResult r = runSingleArmPushing(opt, 1);
      if (lieservo::sim::programs::observationsFailed(opt)) return false;
      if (m.error.empty()) {
        for (const PushingCase& c : r.cases) {
          m.names.push_back(displayName(c.setup.object) + ", " + c.setup.surface.name);
          m.columns.push_back(c.setup.object.name + "_" + c.setup.surface.name + "_error_mm");
          m.objects.push_back(c.setup.object);
        }
        m.error.assign(r.cases.size(),
                       std::vector<std::vector<double>>(m.yaws.size(), std::vector<double>(m.offsets.size())));
      }
      for (std::size_t c = 0; c < r.cases.size(); ++c) {
        const PushTrial& t = r.cases[c].trials.front();
        m.error[c][i][j] = t.terminated ? t.target_error : NAN;
        m.any_miss[i][j] = m.any_miss[i][j] || miss(t);
      }
    }
    std::printf("  yaw %+.1f deg done\n", m.yaws[i]);
    std::fflush(stdout);
  }
  return true;
}

void printTables(const StartMap& m) {
  std::printf("\ntarget error (mm) per case; rows: yaw (deg), columns: sideways offset (mm); * a miss "
              "(> %.0f mm), - not reached\n",
              Bounds::pushing_error_max);
  for (std::size_t c = 0; c < m.names.size(); ++c) {
    std::printf("\n%s\n%10s", m.names[c].c_str(), "yaw\\off");
    for (const double o : m.offsets) std::printf(" %6.1f ", o);
    std::printf("\n");
    for (std::size_t i = 0; i < m.yaws.size(); ++i) {
      std::printf("%10.1f", m.yaws[i]);
      for (std::size_t j = 0; j < m.offsets.size(); ++j) {
        const double e = m.error[c][i][j];
        if (std::isnan(e)) std::printf("      - ");
        else std::printf(" %6.2f%s", e, e > Bounds::pushing_error_max ? "*" : " ");
      }
      std::printf("\n");
    }
  }
}

// One row per start, one column per case: its target error (mm), nan when not reached.
bool writeCsv(const StartMap& m, const std::string& path) {
  std::vector<std::string> header = {"offset_mm", "yaw_deg"};
  header.insert(header.end(), m.columns.begin(), m.columns.end());
  CsvWriter csv;
  if (!csv.open(path, header)) return false;
  for (std::size_t i = 0; i < m.yaws.size(); ++i)
    for (std::size_t j = 0; j < m.offsets.size(); ++j) {
      std::vector<double> row = {m.offsets[j], m.yaws[i]};
      for (std::size_t c = 0; c < m.names.size(); ++c) row.push_back(m.error[c][i][j]);
      csv.row(row);
    }
  return csv.close();
}

void printLeverArmsAndMisses(const StartMap& m) {
  std::printf("\nthe miss against the push's initial lever arm d0 = offset - A sin(yaw) (the contact's distance "
              "along the face\nfrom the perpendicular through the object's centre), fitted as g |d0 - d*|:\n");
  for (std::size_t c = 0; c < m.names.size(); ++c) {
    if (isRound(m.objects[c])) continue;  // never turned: yaw does not move the contact
    const LeverArmFit f = fitLeverArm(m.offsets, m.yaws, m.error[c]);
    std::printf("  %-24s A %5.1f mm (centre to face %5.1f mm), d* %+.2f mm, g %.2f, rms residual %.2f mm\n",
                m.names[c].c_str(), f.A, mujoco::halfExtentX(m.objects[c]), f.d_star, f.gain, f.rms);
  }
  int misses = 0;
  double p = 0;
  std::printf("\nstarts that miss in at least one case:");
  for (std::size_t i = 0; i < m.yaws.size(); ++i)
    for (std::size_t j = 0; j < m.offsets.size(); ++j)
      if (m.any_miss[i][j]) {
        ++misses;
        p += cellProbability(m.yaws, i, m.yaw_step) * cellProbability(m.offsets, j, m.offset_step);
        std::printf(" (%+.1f mm, %+.1f deg)", m.offsets[j], m.yaws[i]);
      }
  std::printf("%s\n", misses ? "" : " none");
  if (std::abs(m.max_offset - kClip * kDrawSd) < 1e-9 && std::abs(m.max_yaw - kClip * kDrawSd) < 1e-9) {
    // The demo's trial i of a seed draws one placement for all eight cases.
    std::printf("the demo's draw lands on them with probability %.2g per trial (each point standing for its "
                "cell), %.2g per seed of 5 trials\n",
                p, 1 - std::pow(1 - p, 5));
  }
}

int run(int argc, char** argv) {
  StartMap m;
  lieservo::sim::programs::ObservationChoice obs;
  TaskOptions opt;
  std::string out_csv, note, why;
  if (const int status = parseOptions(argc, argv, m, obs, opt, out_csv); status >= 0) return status;
  if (const int status = lieservo::sim::programs::setUpObservations(obs, opt, note); status >= 0) return status;
  if (!out_csv.empty() && !cli::mayOverwrite("--out", out_csv, kCsvStart, why)) {  // before the minutes of pushing
    std::fprintf(stderr, "%s\n", why.c_str());
    return cli::kUsageOrSetup;
  }
  if (!note.empty()) std::printf("%s\n", note.c_str());
  opt.support_friction_scale = 1.0;
  std::printf("single-arm pushing from fixed start placements, %zu offsets x %zu yaws, mu_s nominal, "
              "observations: %s\n",
              m.offsets.size(), m.yaws.size(), opt.observations ? "real" : "gaussian");
  if (!pushFromEveryStart(m, opt)) return cli::kUsageOrSetup;
  printTables(m);
  if (!out_csv.empty() && !writeCsv(m, out_csv)) {
    std::fprintf(stderr, "--out %s: cannot write it\n", out_csv.c_str());
    return cli::kUsageOrSetup;
  }
  printLeverArmsAndMisses(m);
  return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) {
  return cli::runProgram("lieservo_push_start_map", [&] { return run(argc, argv); });
}
