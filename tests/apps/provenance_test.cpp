// SPDX-License-Identifier: Apache-2.0
// Provenance: SHA-256 against known digests and coreutils' sha256sum, the job's input files, and
// the lines written into PLY, VTK and OpenVDB files.
#include "io/provenance.h"

#include <gtest/gtest.h>
#include <morph/exceptions.h>

#include <cstdlib>
#include <fstream>

#include "apps/command_support.h"

namespace {

class ProvenanceTest : public morphmill_test::ScratchDirTest {};

TEST_F(ProvenanceTest, Sha256MatchesKnownDigests) {
  // FIPS 180-2 examples.
  EXPECT_EQ(morphmill::sha256_of_file(write_text("abc", "abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(morphmill::sha256_of_file(write_text("empty", "")),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // A file longer than one read buffer, against an independent implementation.
  std::string big(300000, '\0');
  for (std::size_t i = 0; i < big.size(); ++i) big[i] = char((i * 7919) % 251);
  const std::string path = write_text("big", big);
  const auto sha256sum = morphmill_test::run_command("sha256sum " + path);
  if (sha256sum.exit_code == 0) {
    EXPECT_EQ(sha256sum.output.substr(0, 64), morphmill::sha256_of_file(path));
  }
  EXPECT_THROW(morphmill::sha256_of_file(path + ".missing"), morph::IoError);
}

TEST_F(ProvenanceTest, RecordsInputsOptionsAndTheCommandLine) {
  const char* argv[] = {"morphmill", "verify", "my job.json", "--out", "o"};
  morphmill::record_command_line(5, argv);
  setenv("SOURCE_DATE_EPOCH", "86400", 1);
  const morphmill::Provenance p =
      morphmill::make_provenance({write_text("job.json", "{}")}, {{"voxel", 0.25}}, "mm");
  unsetenv("SOURCE_DATE_EPOCH");
  EXPECT_EQ(p.command_line, "morphmill verify 'my job.json' --out o");
  ASSERT_EQ(p.inputs.size(), 1u);
  EXPECT_EQ(p.inputs[0].sha256, "44136fa355b3678a1146ad16f7e8649e94fb4fc21fe77e8310c060f61caaff8a");
  EXPECT_EQ(p.inputs[0].bytes, 2u);
  EXPECT_EQ(p.date_utc, "1970-01-02T00:00:00Z");
  EXPECT_FALSE(p.version.empty());
  EXPECT_GE(p.threads, 1u);
  const nlohmann::json j = morphmill::to_json(p);
  EXPECT_EQ(j["options"]["voxel"].get<double>(), 0.25);
  EXPECT_EQ(j["units"], "mm");
  bool has_input_line = false;
  for (const std::string& line : morphmill::provenance_lines(p)) {
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
    if (line.find(p.inputs[0].sha256) != std::string::npos) has_input_line = true;
  }
  EXPECT_TRUE(has_input_line);
}

TEST_F(ProvenanceTest, JobInputsAreTheJobAndTheFilesItReads) {
  morph::Job job;
  job.file = write_text("job.json", "{}");
  job.paths.resize(2);
  job.paths[0].source = write_text("a.nc", "G0 X0");
  job.paths[1].source = "paths[1].polyline";  // not a file
  job.stock.mesh_path = job.paths[0].source;  // listed once
  EXPECT_EQ(morphmill::job_input_files(job), (std::vector<std::string>{job.file, job.paths[0].source}));
}

}  // namespace
