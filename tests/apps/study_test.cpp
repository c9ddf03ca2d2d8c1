// SPDX-License-Identifier: Apache-2.0
// `morphmill study`: the least-squares order on synthetic data, the zigzag job builder, the study
// file checks, PLplot pictures, and a small study through the binary.
#include <gtest/gtest.h>

#include <morph/exceptions.h>
#include "apps/command_support.h"

#include <array>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "campaigns/study.h"

namespace fs = std::filesystem;
using namespace morphmill::study;

namespace {

fs::path scratch(const std::string& name) {
  return morphmill_test::scratch_dir("study_test", name);
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// Width and height from a PNG's IHDR chunk; (0, 0) if the file is not a PNG.
std::pair<int, int> png_size(const fs::path& path) {
  const std::string bytes = slurp(path);
  if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) return {0, 0};
  auto be32 = [&](std::size_t at) {
    int value = 0;
    for (int i = 0; i < 4; ++i) value = value * 256 + static_cast<unsigned char>(bytes[at + i]);
    return value;
  };
  return {be32(16), be32(20)};
}

int run(const std::string& command, std::string* output) {
  const morphmill_test::CommandResult result = morphmill_test::run_command(command);
  *output += result.output;
  return result.exit_code;
}

}  // namespace

TEST(StudyFit, OrderOfAnExactPowerLawIsExact) {
  const std::vector<double> x = {1.0, 0.5, 0.25, 0.125, 0.0625};
  for (double order : {1.0, 1.7, 2.0}) {
    std::vector<double> y;
    for (double h : x) y.push_back(3.0 * std::pow(h, order));
    const PowerFit fit = fit_power_law(x, y);
    EXPECT_NEAR(fit.order, order, 1e-12);
    EXPECT_NEAR(fit.constant, 3.0, 1e-12);
    EXPECT_NEAR(fit.r_squared, 1.0, 1e-12);
    EXPECT_EQ(fit.points, x.size());
  }
}

TEST(StudyFit, LeastSquaresSlopeOfNoisyDataAndBadInput) {
  // log y = 2 log x + e with e = +d, -d, +d, -d at log x = 0, 1, 2, 3. Least squares gives the
  // slope 2 + sum((lx - mean) e) / sum((lx - mean)^2) = 2 - 0.4 d.
  const double d = 0.1;
  std::vector<double> x, y;
  double sxx = 0, sxe = 0;
  for (int i = 0; i < 4; ++i) {
    const double lx = i, e = (i % 2 == 0 ? d : -d);
    x.push_back(std::exp(lx));
    y.push_back(std::exp(2 * lx + e));
    sxx += (lx - 1.5) * (lx - 1.5);
    sxe += (lx - 1.5) * e;
  }
  EXPECT_NEAR(sxe / sxx, -0.4 * d, 1e-15);
  EXPECT_NEAR(fit_power_law(x, y).order, 2 - 0.4 * d, 1e-12);
  EXPECT_THROW(fit_power_law({1.0}, {1.0}), morph::InputError);
  EXPECT_THROW(fit_power_law({1.0, 1.0}, {1.0, 2.0}), morph::InputError);
  EXPECT_THROW(fit_power_law({1.0, -2.0}, {1.0, 2.0}), morph::InputError);  // one usable pair
}

TEST(StudyZigzag, PassesAreStepOverApartAtTheDepth) {
  ZigzagSpec spec;
  spec.name = "z";
  spec.stock_min = {0, 0, 0};
  spec.stock_max = {30, 20, 8};
  spec.tool_type = "ballend";
  spec.tool_radius = 2;
  spec.tool_length = 20;
  spec.x0 = -3;
  spec.y0 = 4;
  spec.x1 = 33;
  spec.y1 = 16;
  spec.depth = 1.5;
  spec.step_over = 3;
  const morph::Job job = make_zigzag_job(spec);
  // y = 4, 7, 10, 13, 16: five passes joined by four steps.
  ASSERT_EQ(job.move_count(), 9u);
  const auto moves = job.moves();
  for (std::size_t i = 0; i < moves.size(); i += 2) {
    EXPECT_DOUBLE_EQ(moves[i]->start.y(), 4 + 3.0 * (i / 2));
    EXPECT_DOUBLE_EQ(moves[i]->start.z(), 8 - 1.5);  // ball-end: the tool point is the tip
    EXPECT_DOUBLE_EQ(std::abs(moves[i]->end.x() - moves[i]->start.x()), 36);
  }
  spec.tool_type = "sphere";
  EXPECT_DOUBLE_EQ(make_zigzag_job(spec).moves()[0]->start.z(), 8 - 1.5 + 2);  // sphere: the centre
  spec.step_over = 0;
  EXPECT_THROW(make_zigzag_job(spec), morph::InputError);
}

TEST(StudyFile, ErrorsNameTheFileAndThePath) {
  const nlohmann::json good = {{"jobs", {"a.json"}}, {"sweep", {{"voxel_size", {0.5, 0.25}}}}};
  const StudySpec spec = parse_study(good, "/studies/s.json");
  EXPECT_EQ(spec.job_paths, std::vector<std::string>{"/studies/a.json"});
  EXPECT_EQ(spec.voxel_sizes, (std::vector<double>{0.5, 0.25}));
  auto message = [](const nlohmann::json& json) {
    try {
      parse_study(json, "s.json");
    } catch (const morph::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(
      message({{"jobs", {"a.json"}}, {"sweep", {{"voxel", {0.5}}}}}).find("s.json: sweep.voxel: unknown key"),
      std::string::npos);
  EXPECT_NE(message({{"jobs", {"a.json"}}, {"sweep", {{"tolerance", {0.1, -1}}}}}).find("sweep.tolerance[1]"),
            std::string::npos);
  EXPECT_NE(message({{"jobs", {"a.json"}}, {"sweep", nlohmann::json::object()}}).find("nothing to sweep"),
            std::string::npos);
  EXPECT_NE(message({{"jobs", {"a.json"}}, {"sweep", {{"step_over", {1}}}}}).find("needs zigzag_jobs"),
            std::string::npos);
}

TEST(StudyPlot, WritesAPngOfTheAskedSize) {
  const fs::path dir = scratch("plot");
  PlotSpec spec;
  spec.title = "test";
  spec.x_label = "x";
  spec.y_label = "y";
  spec.width = 320;
  spec.height = 240;
  spec.series.push_back({"y = x^2", {0.1, 1, 10}, {0.01, 1, 100}});
  plot_png(spec, (dir / "plot.png").string());
  EXPECT_EQ(png_size(dir / "plot.png"), (std::pair<int, int>{320, 240}));
  PlotSpec empty = spec;
  empty.series = {{"negative on a log axis", {-1}, {-1}}};
  EXPECT_THROW(plot_png(empty, (dir / "empty.png").string()), morph::InputError);
}

// A small study through the binary: two voxel sizes and two tolerances on the single slot.
TEST(StudyRun, SmallStudyWritesTableAndPictures) {
  const fs::path dir = scratch("run");
  const nlohmann::json study = {{"name", "small"},
                                {"jobs", {std::string(MORPHMILL_TEST_DATA) + "/jobs/single_slot.json"}},
                                {"sweep", {{"voxel_size", {0.5, 0.25}}, {"tolerance", {0.05, 0.02}}}},
                                {"baseline", {{"voxel_size", 0.5}}},
                                {"samples", 2000},
                                {"image_size", {200, 150}}};
  std::ofstream(dir / "small.json") << study.dump(2);
  std::string output;
  const int code = run(std::string(MORPHMILL_BINARY) + " study " + (dir / "small.json").string() + " --out " +
                           (dir / "out").string(),
                       &output);
  ASSERT_EQ(code, 0) << output;
  const fs::path out = dir / "out";
  std::istringstream csv(slurp(out / "study.csv"));
  std::string line;
  int lines = 0;
  while (std::getline(csv, line)) ++lines;
  EXPECT_EQ(lines, 1 + 4);  // header + 2 voxel sizes + 2 tolerances
  for (const char* png : {"error_vs_voxel.png", "time_vs_accuracy.png", "memory_vs_accuracy.png"})
    EXPECT_GT(png_size(out / png).first, 0) << png;
  const auto json = nlohmann::json::parse(slurp(out / "study.json"));
  ASSERT_EQ(json["rows"].size(), 4u);
  for (const auto& row : json["rows"]) {
    EXPECT_EQ(row["error"], "") << row.dump();
    EXPECT_EQ(row["pictures"].size(), 2u);
    for (const auto& picture : row["pictures"])
      EXPECT_EQ(png_size(out / picture.get<std::string>()).first, 200);
  }
  // The reference's error shrinks with the voxel: a positive fitted order for every measure.
  int fits = 0;
  for (const auto& fit : json["convergence"])
    if (fit["measure"] == "mean" || fit["measure"] == "rms") {
      EXPECT_GT(fit["order"].get<double>(), 0.0) << fit.dump();
      ++fits;
    }
  EXPECT_EQ(fits, 2);
  const std::string html = slurp(out / "report.html");
  EXPECT_NE(html.find("data:image/png;base64,"), std::string::npos);
  EXPECT_EQ(html.find("src=\"error_vs_voxel.png\""), std::string::npos);  // embedded, not linked
}

namespace {

/// Requests a stop (as SIGINT does) once `after` settings have been counted.
struct StopAfterSettings : morph::Progress {
  std::atomic<int>* stop;
  std::size_t after, counted = 0;
  StopAfterSettings(std::atomic<int>* s, std::size_t a) : stop(s), after(a) {}
  void advance(std::size_t done) override {
    if ((counted += done) >= after) stop->store(SIGINT);
  }
};

}  // namespace

// A stop lets no further setting start, writes the table of what ran (complete: false) and no
// report; --resume keeps the evaluated setting and evaluates the rest.
TEST(StudyRun, StopsCleanlyAndResumes) {
  const fs::path dir = scratch("stop");
  const nlohmann::json study = {{"name", "stop"},
                                {"jobs", {std::string(MORPHMILL_TEST_DATA) + "/jobs/single_slot.json"}},
                                {"sweep", {{"voxel_size", {0.5, 0.4}}}},
                                {"samples", 500},
                                {"heatmaps", false}};
  std::ofstream(dir / "stop.json") << study.dump(2);
  morphmill::study::StudyOptions options;
  options.study_path = (dir / "stop.json").string();
  options.out_dir = (dir / "out").string();
  std::atomic<int> stop{0};
  StopAfterSettings stop_after(&stop, 1);
  options.stop_signal = &stop;
  options.progress = &stop_after;
  const auto stopped = morphmill::study::run_study(options);
  EXPECT_FALSE(stopped.complete());
  EXPECT_EQ(stopped.stopped, "interrupted by SIGINT");
  EXPECT_EQ(stopped.settings, 2u);
  EXPECT_EQ(stopped.evaluated, 1u);
  ASSERT_EQ(stopped.rows.size(), 1u);
  const auto json = nlohmann::json::parse(slurp(dir / "out" / "study.json"));
  EXPECT_EQ(json["complete"], false);
  EXPECT_EQ(json["rows"].size(), 1u);
  EXPECT_FALSE(fs::exists(dir / "out" / "report.html"));

  options.stop_signal = nullptr;
  options.progress = nullptr;
  options.resume = true;
  const auto resumed = morphmill::study::run_study(options);
  EXPECT_TRUE(resumed.complete());
  ASSERT_EQ(resumed.rows.size(), 2u);
  // The first setting was kept, not evaluated again: the same measured time to the last digit.
  EXPECT_EQ(resumed.rows[0].generator_seconds, stopped.rows[0].generator_seconds);
  EXPECT_EQ(resumed.rows[0].reference_max_error, stopped.rows[0].reference_max_error);
  EXPECT_TRUE(fs::exists(dir / "out" / "report.html"));
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "out" / "study.json"))["complete"], true);
}
