// SPDX-License-Identifier: Apache-2.0
// What every command shares on its command line (apps/src/cli/cli_conventions.h): -o/--output with
// --out still accepted, --json [FILE], -q/-v/--threads everywhere, suggestions for typos, the
// bash completion, and progress lines with timestamps when stderr is not a terminal.
#include "cli/cli_conventions.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <thread>

#include "apps/command_support.h"
#include "cli/terminal_progress.h"

namespace {

namespace fs = std::filesystem;
using morphmill_test::run_command;
const std::string kData = MORPHMILL_TEST_DATA;

class CliConventions : public morphmill_test::ScratchDirTest {
 protected:
  morphmill_test::CommandResult morphmill(const std::string& arguments) const {
    return run_command(std::string("'") + MORPHMILL_BINARY + "' " + arguments);
  }
};

const std::vector<std::string> kCommands = {"info",   "mesh-info", "erode",    "reference", "deviation",
                                            "render", "verify",    "compare",  "stress",    "stress-merge",
                                            "study",  "erode2d",   "verify2d", "completion"};

TEST(NearestName, FindsLikelyTyposOnly) {
  const std::vector<std::string> commands = {"verify", "verify2d", "erode", "erode2d", "reference"};
  EXPECT_EQ(morphmill::nearest_name("verfy", commands), "verify");
  EXPECT_EQ(morphmill::nearest_name("erod", commands), "erode");
  EXPECT_EQ(morphmill::nearest_name("refrence", commands), "reference");
  EXPECT_EQ(morphmill::nearest_name("zzz", commands), "");
  EXPECT_EQ(morphmill::nearest_name("--tolerence", {"--tolerance", "--threads"}), "--tolerance");
}

TEST_F(CliConventions, EveryCommandsHelpShowsTheSharedOptions) {
  for (const std::string& command : kCommands) {
    const auto r = morphmill(command + " --help");
    ASSERT_EQ(r.exit_code, 0) << command << ": " << r.output;
    EXPECT_NE(r.output.find("-q,--quiet"), std::string::npos) << command << ": " << r.output;
    EXPECT_NE(r.output.find("-v,--verbose"), std::string::npos) << command << ": " << r.output;
    EXPECT_NE(r.output.find("--threads"), std::string::npos) << command << ": " << r.output;
    // One spelling of the output option: never `--out` on its own.
    EXPECT_FALSE(std::regex_search(r.output, std::regex("--out[^p]"))) << command << ": " << r.output;
  }
  for (const char* command : {"erode", "reference", "verify", "compare", "stress", "study", "erode2d"}) {
    const auto r = morphmill(std::string(command) + " --help");
    EXPECT_NE(r.output.find("-o,--output"), std::string::npos) << command << ": " << r.output;
  }
}

TEST_F(CliConventions, OutputAndTheOldOutSpellingBothWork) {
  const std::string job = kData + "/planar/figure9.json";
  auto r = morphmill("erode2d '" + job + "' --output '" + path("a.svg") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = morphmill("erode2d '" + job + "' --out '" + path("b.svg") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = morphmill("erode2d '" + job + "' --out='" + path("c.svg") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"a.svg", "b.svg", "c.svg"}) EXPECT_GT(fs::file_size(path(name)), 0u) << name;
}

TEST_F(CliConventions, MistypedCommandsAndOptionsGetASuggestion) {
  auto r = morphmill("verfy '" + kData + "/jobs/slots.json'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("did you mean 'verify'"), std::string::npos) << r.output;
  r = morphmill("erode '" + kData + "/jobs/slots.json' -o x.ply --tolerence 0.1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("did you mean '--tolerance'"), std::string::npos) << r.output;
  r = morphmill("info '" + kData + "/jobs/slots.json' --jsn");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("did you mean '--json'"), std::string::npos) << r.output;
}

TEST_F(CliConventions, JsonGoesToStandardOutputOrToAFile) {
  const std::string job = kData + "/jobs/slots.json";
  // Both places of the flag, as before: the summary on standard output.
  for (const std::string& arguments : {"info --json '" + job + "'", "info '" + job + "' --json"}) {
    const auto r = morphmill(arguments + " 2>/dev/null");
    ASSERT_EQ(r.exit_code, 0) << arguments << ": " << r.output;
    EXPECT_EQ(nlohmann::json::parse(r.output)["moves"]["total"], 8) << arguments;
  }
  const auto r = morphmill("info '" + job + "' --json '" + path("info.json") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(path("info.json"));
  EXPECT_EQ(nlohmann::json::parse(in)["moves"]["total"], 8);
  EXPECT_EQ(morphmill("info --json").exit_code, 2);
}

TEST_F(CliConventions, ErodeWritesItsSummaryAsJson) {
  const auto r = morphmill("erode '" + kData + "/jobs/single_slot.json' -o '" + path("part.ply") +
                           "' --allow-open --json '" + path("erode.json") + "'");
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.output;
  std::ifstream in(path("erode.json"));
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["closed_manifold"].get<bool>() && summary["self_intersecting_pairs"] == 0,
            r.exit_code == 0);
  EXPECT_GT(summary["triangles"].get<int>(), 0);
  EXPECT_EQ(summary["units"], "mm");
  EXPECT_EQ(summary["output"], path("part.ply"));
}

// verify, compare, stress, stress-merge and study write their JSON summary into --output as
// before; `--json [FILE]` writes the same document to FILE, or alone on standard output.
class JsonSummaries : public CliConventions {
 protected:
  /// Runs `arguments` with standard error discarded, so the output is standard output alone.
  morphmill_test::CommandResult stdout_of(const std::string& arguments) const {
    return run_command(std::string("('") + MORPHMILL_BINARY + "' " + arguments + " 2>/dev/null)");
  }
  nlohmann::json read(const std::string& file) const {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  }
};

TEST_F(JsonSummaries, VerifyWritesDeviationJsonToAFileOrToStandardOutput) {
  const std::string job = kData + "/jobs/single_slot.json";
  const std::string fast = " --reference-only --voxel 0.5 --samples 2000";
  const auto to_file = morphmill("verify '" + job + "' -o '" + path("a") + "'" + fast + " --json '" +
                                 path("verify.json") + "'");
  ASSERT_EQ(to_file.exit_code, 0) << to_file.output;
  EXPECT_NE(to_file.output.find("verdict HOLDS"), std::string::npos) << to_file.output;
  const nlohmann::json written = read(path("verify.json"));
  EXPECT_EQ(written, read(path("a") + "/deviation.json"));
  EXPECT_EQ(written["format"], "morphmill-verify");
  EXPECT_TRUE(written["verdict"]["holds"].get<bool>()) << written["verdict"];

  const auto to_stdout = stdout_of("verify '" + job + "' -o '" + path("b") + "'" + fast + " --json");
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.output;
  EXPECT_EQ(nlohmann::json::parse(to_stdout.output), read(path("b") + "/deviation.json"));
}

TEST_F(JsonSummaries, CompareWritesItsSummaryAlsoWithoutAnOutputDirectoryAndWhenOutOfTheBand) {
  const std::string job = kData + "/jobs/design_gouge_excess.json";
  const auto with_dir = stdout_of("compare '" + job + "' -o '" + path("c") + "' --samples 2000 --json -");
  ASSERT_EQ(with_dir.exit_code, 1) << with_dir.output;  // this design is gouged: out of the band
  const nlohmann::json summary = nlohmann::json::parse(with_dir.output);
  EXPECT_EQ(summary, read(path("c") + "/compare.json"));
  EXPECT_EQ(summary["format"], "morphmill-compare");
  EXPECT_FALSE(summary["within_band"].get<bool>());

  const auto without_dir =
      morphmill("compare '" + job + "' --samples 2000 --json '" + path("compare.json") + "'");
  ASSERT_EQ(without_dir.exit_code, 1) << without_dir.output;
  EXPECT_NE(without_dir.output.find("OUT OF THE BAND"), std::string::npos) << without_dir.output;
  const nlohmann::json alone = read(path("compare.json"));
  EXPECT_EQ(alone["per_point"], summary["per_point"]);  // same run, same numbers
  EXPECT_EQ(alone["regions"], summary["regions"]);
}

TEST_F(JsonSummaries, StressAndStressMergeWriteSummaryJson) {
  const auto run = morphmill("stress --cases 2 --seed 3 --samples 200 --threads 1 -o '" + path("s") +
                             "' --json '" + path("stress.json") + "'");
  ASSERT_TRUE(run.exit_code == 0 || run.exit_code == 1) << run.output;
  const nlohmann::json summary = read(path("stress.json"));
  EXPECT_EQ(summary, read(path("s") + "/summary.json"));
  EXPECT_EQ(summary["cases_run"], 2);
  EXPECT_EQ(summary["failed_cases"].get<int>() > 0, run.exit_code == 1);

  const auto merged = stdout_of("stress-merge '" + path("s") + "' -o '" + path("m") + "' --json");
  ASSERT_EQ(merged.exit_code, run.exit_code) << merged.output;
  const nlohmann::json merged_summary = nlohmann::json::parse(merged.output);
  EXPECT_EQ(merged_summary, read(path("m") + "/summary.json"));
  EXPECT_TRUE(merged_summary["merged"].get<bool>());
  EXPECT_EQ(merged_summary["cases_run"], 2);
}

TEST_F(JsonSummaries, DeviationWritesItsStatisticsToStandardOutputAlone) {
  const std::string cube = kData + "/meshes/cube.stl";
  const auto r = stdout_of("deviation '" + cube + "' '" + cube + "' --samples 500 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json stats = nlohmann::json::parse(r.output);
  EXPECT_EQ(stats["format"], "morphmill-deviation");
  EXPECT_LT(stats["hausdorff"].get<double>(), 1e-9);  // a mesh against itself
  const auto to_file = morphmill("deviation '" + cube + "' '" + cube + "' --samples 500 --json '" +
                                 path("deviation.json") + "'");
  ASSERT_EQ(to_file.exit_code, 0) << to_file.output;
  EXPECT_NE(to_file.output.find("Hausdorff distance"), std::string::npos) << to_file.output;
  EXPECT_EQ(read(path("deviation.json"))["a_to_b"], stats["a_to_b"]);
}

TEST_F(JsonSummaries, StudyWritesStudyJson) {
  const nlohmann::json study = {{"name", "json"},
                                {"jobs", {kData + "/jobs/single_slot.json"}},
                                {"sweep", {{"voxel_size", {0.5}}}},
                                {"samples", 1000},
                                {"image_size", {100, 80}}};
  const std::string file = write_text("study.json", study.dump(2));
  const auto r = stdout_of("study '" + file + "' -o '" + path("out") + "' --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json table = nlohmann::json::parse(r.output);
  EXPECT_EQ(table, read(path("out") + "/study.json"));
  ASSERT_EQ(table["rows"].size(), 1u);
  EXPECT_EQ(table["rows"][0]["error"], "");
}

TEST_F(JsonSummaries, ReferenceWritesOneDocumentPerVoxelSizeOrOneArrayOnStandardOutput) {
  const std::string job = kData + "/jobs/single_slot.json";
  const auto one = stdout_of("reference '" + job + "' --voxel 0.5 -o '" + path("r.ply") + "' --json");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const nlohmann::json alone = nlohmann::json::parse(one.output);  // no summary lines around it
  EXPECT_EQ(alone["format"], "morphmill-reference");
  EXPECT_EQ(alone["units"], "mm");

  const auto several =
      stdout_of("reference '" + job + "' --voxel 0.5,0.4 -o '" + path("s.ply") + "' --json -");
  ASSERT_EQ(several.exit_code, 0) << several.output;
  const nlohmann::json runs = nlohmann::json::parse(several.output);
  ASSERT_TRUE(runs.is_array());
  ASSERT_EQ(runs.size(), 2u);
  // Each run's pieces match the file written for that voxel size, and a finer voxel gives a volume
  // nearer the slot's: both within a few percent of each other, the runs really differ.
  const auto to_files = morphmill("reference '" + job + "' --voxel 0.5,0.4 -o '" + path("f.ply") +
                                  "' --json '" + path("f.json") + "'");
  ASSERT_EQ(to_files.exit_code, 0) << to_files.output;
  for (const char* voxel : {"0.5", "0.4"}) {
    const nlohmann::json file = read(path("f_v") + voxel + ".json");
    const nlohmann::json& run = runs[std::string(voxel) == "0.5" ? 0 : 1];
    EXPECT_EQ(file["pieces"].size(), run["pieces"].size()) << voxel;
    EXPECT_DOUBLE_EQ(file["pieces"][0]["volume"].get<double>(), run["pieces"][0]["volume"].get<double>())
        << voxel;
  }
  EXPECT_NE(runs[0]["pieces"][0]["volume"], runs[1]["pieces"][0]["volume"]);
}

TEST_F(JsonSummaries, Verify2dWritesReportJsonToAFileOrToStandardOutput) {
  const std::string job = kData + "/planar/figure13.json";
  const auto to_stdout = stdout_of("verify2d '" + job + "' -o '" + path("v") + "' --json");
  ASSERT_EQ(to_stdout.exit_code, 0) << to_stdout.output;
  const nlohmann::json summary = nlohmann::json::parse(to_stdout.output);
  EXPECT_EQ(summary, read(path("v") + "/report.json"));
  EXPECT_EQ(summary["format"], "morphmill-verify2d");
  EXPECT_EQ(summary["format_version"], 1);
  EXPECT_EQ(summary["units"], "mm");
  EXPECT_TRUE(summary["verdict"]["holds"].get<bool>());
  ASSERT_EQ(summary["provenance"]["inputs"].size(), 1u);
  EXPECT_EQ(summary["provenance"]["inputs"][0]["sha256"].get<std::string>().size(), 64u);

  const auto to_file =
      morphmill("verify2d '" + job + "' -o '" + path("w") + "' --json '" + path("v2d.json") + "'");
  ASSERT_EQ(to_file.exit_code, 0) << to_file.output;
  EXPECT_NE(to_file.output.find("verdict HOLDS"), std::string::npos) << to_file.output;
  EXPECT_EQ(read(path("v2d.json"))["exact"]["area"], summary["exact"]["area"]);
}

TEST_F(CliConventions, ThreadsIsCheckedOnEveryCommand) {
  const auto r = morphmill("info '" + kData + "/jobs/slots.json' --threads -1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
  EXPECT_EQ(morphmill("info '" + kData + "/jobs/slots.json' --threads 1 -q").exit_code, 0);
}

TEST_F(CliConventions, BashCompletionCompletesCommandsAndOptions) {
  const auto script = morphmill("completion bash > '" + path("completion.bash") + "'");
  ASSERT_EQ(script.exit_code, 0) << script.output;
  const auto complete = [&](const std::string& words, int current) {
    return run_command("bash -c 'source \"" + path("completion.bash") + "\"; COMP_WORDS=(" + words +
                       "); COMP_CWORD=" + std::to_string(current) +
                       "; _morphmill; echo \"${COMPREPLY[*]}\"'");
  };
  auto r = complete("morphmill ver", 1);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "verify verify2d\n");
  r = complete("morphmill erode job.json --tol", 3);
  EXPECT_EQ(r.output, "--tolerance\n");
  r = complete("morphmill stress --resu", 2);
  EXPECT_EQ(r.output, "--resume\n");
}

TEST_F(CliConventions, VerboseDeviationSaysEachStageOnTimestampedLines) {
  const std::string cube = kData + "/meshes/cube.stl";
  const auto r = run_command(std::string("('") + MORPHMILL_BINARY + "' deviation '" + cube + "' '" + cube +
                             "' --samples 2000 -v 2> '" + path("err") + "' > /dev/null)");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(path("err"));
  const std::string lines((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string stamp = R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ )";
  for (const char* stage : {"reading [^\n]*cube.stl", "indexing [^\n]*cube.stl", "measuring \\d+ samples"})
    EXPECT_TRUE(std::regex_search(lines, std::regex(stamp + stage + R"(: 100% done in \d+\.\d s)")))
        << stage << "\n"
        << lines;
  const auto quiet = run_command(std::string("('") + MORPHMILL_BINARY + "' deviation '" + cube + "' '" +
                                 cube + "' --samples 2000 -q 2> '" + path("quiet_err") + "' > /dev/null)");
  ASSERT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(fs::file_size(path("quiet_err")), 0u);
}

TEST(TerminalProgressLines, TimestampedEndLineWhenNotATerminalAndNothingWhenQuiet) {
  const auto run_stage = [] {
    morphmill::TerminalProgress progress;  // tests run with stderr redirected: log lines
    progress.begin("stage under test", 10);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    progress.advance(10);
    progress.end();
  };
  testing::internal::CaptureStderr();
  run_stage();
  const std::string lines = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(std::regex_search(
      lines, std::regex(R"(^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ stage under test: 100% done in \d+\.\d s\n)")))
      << lines;
  morphmill::global_options().quiet = true;
  testing::internal::CaptureStderr();
  run_stage();
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
  morphmill::global_options().quiet = false;
}

}  // namespace
