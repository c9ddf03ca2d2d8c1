// SPDX-License-Identifier: Apache-2.0
// The deviation files other tools read: a PLY whose deviation MeshLab shows as vertex quality and
// CloudCompare as a scalar field, and a VTK PolyData for ParaView. The files are read back as
// those tools read them: with the tools themselves (CloudCompare, meshlabserver, VTK's Python
// reader, which is ParaView's) where installed, skipped otherwise; always by parsing the headers.
#include <gtest/gtest.h>
#include <morphmill/mesh_io.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "apps/command_support.h"
#include "common/test_meshes.h"

namespace fs = std::filesystem;

namespace {

const std::string kBinary = MORPHMILL_BINARY;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

bool have(const std::string& program) {
  return morphmill_test::run_command("command -v " + program + " >/dev/null").exit_code == 0;
}

// A 6 x 6 x 10 mm block inside a 10 x 10 x 10.5 mm one, on the same base: A's top corners lie 0.5
// inside B (gouge, -0.5), its bottom corners on B's base (0).
class DeviationFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(morphmill_test::scratch_dir("deviation_files", "cubes"));
    morph::TriangleMesh a = morphmill_test::box({2, 2, 0}, {8, 8, 10});
    // Face provenance as the generator writes it: move t / 2 on G-code line 100 + t / 2.
    for (std::size_t t = 0; t < a.triangles.size(); ++t)
      a.tags.push_back({morph::PatchKind::SideSweep, std::int32_t(t / 2), std::int32_t(100 + t / 2)});
    morphmill::write_mesh(a, (*dir_ / "a.ply").string());
    morphmill::write_mesh(morphmill_test::box({0, 0, 0}, {10, 10, 10.5}), (*dir_ / "b.ply").string());
    result_ = new morphmill_test::CommandResult(morphmill_test::run_command(
        kBinary + " deviation " + (*dir_ / "a.ply").string() + " " + (*dir_ / "b.ply").string() +
        " --signed --one-sided --units mm --heatmap " + (*dir_ / "heat.ply").string() + " --vtp " +
        (*dir_ / "heat.vtp").string() + " --json " + (*dir_ / "summary.json").string()));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete result_;
  }
  static fs::path* dir_;
  static morphmill_test::CommandResult* result_;
};
fs::path* DeviationFiles::dir_ = nullptr;
morphmill_test::CommandResult* DeviationFiles::result_ = nullptr;

double expected_at(double z) {
  return z > 5 ? -0.5 : 0.0;
}

TEST_F(DeviationFiles, PlyNamesTheDeviationForMeshLabAndCloudCompareWithProvenance) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  const morph::TriangleMesh heat = morphmill::read_mesh((*dir_ / "heat.ply").string());
  ASSERT_NE(heat.scalar("quality"), nullptr);
  ASSERT_NE(heat.scalar("scalar_deviation"), nullptr);
  for (std::size_t v = 0; v < heat.vertices.size(); ++v) {
    EXPECT_NEAR(heat.scalar("quality")->values[v], expected_at(heat.vertices[v].z()), 1e-12);
    EXPECT_EQ(heat.scalar("scalar_deviation")->values[v], heat.scalar("quality")->values[v]);
  }
  const std::string text = slurp(*dir_ / "heat.ply");
  const std::string header = text.substr(0, text.find("end_header"));
  EXPECT_NE(header.find("comment units: mm\n"), std::string::npos) << header;
  EXPECT_NE(header.find("comment program: morphmill "), std::string::npos) << header;
  const std::string a_hash =
      morphmill_test::run_command("sha256sum " + (*dir_ / "a.ply").string()).output.substr(0, 64);
  EXPECT_NE(header.find("a.ply sha256 " + a_hash), std::string::npos) << header;
}

TEST_F(DeviationFiles, JsonSummaryCarriesFormatUnitsAndProvenance) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  const auto j = nlohmann::json::parse(slurp(*dir_ / "summary.json"));
  EXPECT_EQ(j["format"], "morphmill-deviation");
  EXPECT_EQ(j["format_version"], 1);
  EXPECT_EQ(j["units"], "mm");
  EXPECT_EQ(j["provenance"]["inputs"].size(), 2u);
  EXPECT_EQ(j["provenance"]["options"]["mode"], "signed");
  EXPECT_NE(j["provenance"]["command_line"].get<std::string>().find(" deviation "), std::string::npos);
  // Face samples too: A's side faces lie 2 inside B's sides.
  EXPECT_NEAR(j["a_to_b"]["stats"]["min"].get<double>(), -2.0, 1e-9);
}

TEST_F(DeviationFiles, VtpHasNamedPointAndCellDataWithUnits) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  const std::string xml = slurp(*dir_ / "heat.vtp");
  EXPECT_EQ(xml.rfind("<?xml", 0), 0u);
  EXPECT_NE(xml.find("<VTKFile type=\"PolyData\""), std::string::npos);
  EXPECT_NE(xml.find("<Piece NumberOfPoints=\"8\""), std::string::npos);
  EXPECT_NE(xml.find("NumberOfPolys=\"12\""), std::string::npos);
  EXPECT_NE(xml.find("<PointData Scalars=\"deviation\">"), std::string::npos);
  EXPECT_NE(xml.find("<CellData Scalars=\"deviation\">"), std::string::npos);
  const std::regex units(
      "<DataArray type=\"Float64\" Name=\"deviation\"[^>]*>\\s*[A-Za-z0-9+/=]+\\s*"
      "<InformationKey name=\"UNITS_LABEL\" location=\"vtkDataArray\">mm</InformationKey>");
  EXPECT_EQ(std::distance(std::sregex_iterator(xml.begin(), xml.end(), units), std::sregex_iterator()), 2);
  EXPECT_NE(xml.find("<Array type=\"String\" Name=\"provenance\""), std::string::npos);
}

TEST_F(DeviationFiles, CloudCompareShowsTheScalarField) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  if (!have("CloudCompare")) GTEST_SKIP() << "CloudCompare is not installed";
  const fs::path asc = *dir_ / "cc.asc";
  const auto cc = morphmill_test::run_command(
      "QT_QPA_PLATFORM=offscreen timeout 120 CloudCompare -SILENT -AUTO_SAVE OFF -NO_TIMESTAMP -O " +
      (*dir_ / "heat.ply").string() +
      " -EXTRACT_VERTICES -C_EXPORT_FMT ASC -PREC 12 -SEP SPACE -ADD_HEADER -SAVE_CLOUDS FILE " +
      asc.string());
  ASSERT_EQ(cc.exit_code, 0) << cc.output;
  std::istringstream lines(slurp(asc));
  std::string header;
  std::getline(lines, header);
  // CloudCompare drops the "scalar_" prefix: the field is called "deviation".
  std::istringstream names(header.substr(2));
  std::vector<std::string> columns{std::istream_iterator<std::string>(names), {}};
  const auto column = std::find(columns.begin(), columns.end(), "deviation");
  ASSERT_NE(column, columns.end()) << header;
  const std::size_t deviation_column = std::size_t(column - columns.begin());
  int rows = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream row(line);
    std::vector<double> values{std::istream_iterator<double>(row), {}};
    ASSERT_EQ(values.size(), columns.size()) << line;
    EXPECT_NEAR(values[deviation_column], expected_at(values[2]), 1e-9) << line;
    ++rows;
  }
  EXPECT_EQ(rows, 8);
}

TEST_F(DeviationFiles, MeshLabReadsTheDeviationAsVertexQuality) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  if (!have("meshlabserver") || !have("xvfb-run"))
    GTEST_SKIP() << "meshlabserver or xvfb-run is not installed";
  // meshlabserver loads the file and saves what it holds as vertex quality (-m vq).
  const fs::path out = *dir_ / "meshlab.ply";
  const auto ml =
      morphmill_test::run_command("xvfb-run -a -s '-screen 0 640x480x24' timeout 120 meshlabserver -i " +
                                  (*dir_ / "heat.ply").string() + " -o " + out.string() + " -m vq");
  ASSERT_EQ(ml.exit_code, 0) << ml.output;
  const morph::TriangleMesh back = morphmill::read_mesh(out.string());
  ASSERT_NE(back.scalar("quality"), nullptr) << ml.output;
  for (std::size_t v = 0; v < back.vertices.size(); ++v)
    EXPECT_NEAR(back.scalar("quality")->values[v], expected_at(back.vertices[v].z()), 1e-6);
}

TEST_F(DeviationFiles, VtkReaderOfParaViewShowsTheArraysWithUnits) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  const std::string probe = "/usr/bin/python3 -c 'import vtk' 2>/dev/null";
  if (morphmill_test::run_command(probe).exit_code != 0)
    GTEST_SKIP() << "VTK's Python module is not installed";
  const std::string script =
      "import vtk,sys\n"
      "r=vtk.vtkXMLPolyDataReader();r.SetFileName(sys.argv[1]);r.Update()\n"
      "p=r.GetOutput();d=p.GetPointData().GetArray('deviation');c=p.GetCellData().GetArray('deviation')\n"
      "u=d.GetInformation().Get(vtk.vtkDataArray.UNITS_LABEL())\n"
      "f=p.GetFieldData().GetAbstractArray('units').GetValue(0)\n"
      "m=p.GetCellData().GetArray('move');l=p.GetCellData().GetArray('gcode_line')\n"
      "print('points',p.GetNumberOfPoints(),'cells',p.GetNumberOfCells())\n"
      "print('range',*d.GetRange(),'cellrange',*c.GetRange(),'units',u,'field',f,'move',*m.GetRange(),'line',"
      "*l.GetRange())\n"
      "print('active',p.GetPointData().GetScalars().GetName())\n"
      "for i in range(p.GetNumberOfPoints()):\n"
      "  print('z',p.GetPoint(i)[2],'d',d.GetValue(i))\n";
  std::ofstream(*dir_ / "read_vtp.py") << script;
  const auto py = morphmill_test::run_command("/usr/bin/python3 " + (*dir_ / "read_vtp.py").string() + " " +
                                              (*dir_ / "heat.vtp").string());
  ASSERT_EQ(py.exit_code, 0) << py.output;
  EXPECT_NE(py.output.find("points 8 cells 12"), std::string::npos) << py.output;
  EXPECT_NE(
      py.output.find("range -0.5 0.0 cellrange -0.5 0.0 units mm field mm move 0.0 5.0 line 100.0 105.0"),
      std::string::npos)
      << py.output;
  EXPECT_NE(py.output.find("active deviation"), std::string::npos) << py.output;
  EXPECT_EQ(py.output.find("Error"), std::string::npos) << py.output;
  const std::regex point("z ([-0-9.e]+) d ([-0-9.e]+)");
  int points = 0;
  for (auto it = std::sregex_iterator(py.output.begin(), py.output.end(), point);
       it != std::sregex_iterator(); ++it, ++points)
    EXPECT_NEAR(std::stod((*it)[2]), expected_at(std::stod((*it)[1])), 1e-12);
  EXPECT_EQ(points, 8);
}

}  // namespace
