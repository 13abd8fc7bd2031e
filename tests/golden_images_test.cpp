// Golden images: renders of small demo and plotfile datasets through the volstream binary, compared
// with PFMs made by the pre-refactor renderer (commit cf4f0f8; tests/golden/README.md lists them).
// Only the command line and read_pfm are used, so the renderer's C++ API can change under it.
// VOLSTREAM_GOLDEN_BIN overrides the binary under test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "test_util.h"
#include "volstream/io/image.h"

namespace {
namespace fs = std::filesystem;

constexpr float kTolerance = 1e-4f;  // max abs difference per channel (linear RGB)
// The references were rendered by a g++ 12 build, and the suite holds it to them exactly. Other
// compilers round the demos' and samplers' float expressions a little differently, which moves
// a jittered sample across a transfer-function edge here and there: g++ 13 (the GPU machine's)
// put 2 of jet_spp4's values 7.6e-4 off. There a few such values are allowed, none over 1e-2.
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
constexpr size_t kStrayValuesAllowed = 0;
#else
constexpr size_t kStrayValuesAllowed = 8;
#endif
constexpr float kStrayTolerance = 1e-2f;

// Dataset-making commands; {VS} is the binary, {DIR} the dataset directory to write, {PY} python3,
// {SRC} the source tree. Shared by the cases below (each is made once per process).
const char* const kJet = "{VS} demo jet --cells 1e5 --steps 2 -o {DIR} -q";
const char* const kCosmo = "{VS} demo cosmo --cells 1e5 --steps 1 -o {DIR} -q";
const char* const kPlotfile =
    "{PY} {SRC}/tests/golden/make_plotfile.py {DIR}.plt && {VS} convert {DIR}.plt -o {DIR} -q";
#define CAM "--camera-pos 8,14,30 --camera-at 8,0,0 --fov 40 --size 80x64"

struct Case {
  const char* name;     // tests/golden/<name>.pfm
  const char* dataset;  // command writing {DIR}, or "" for none
  const char* args;     // `volstream render` arguments; {DATA} is the dataset; -o is appended
};

// For gtest's failure messages.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

const Case kCases[] = {
    {"jet_dvr_default_camera", kJet, "{DATA} --step 1 --size 80x64"},
    {"jet_dvr", kJet, "{DATA} --step 1 " CAM},
    {"jet_dvr_log", kJet, "{DATA} --field velocity --log --tf inferno " CAM},
    {"jet_iso", kJet, "{DATA} --step 1 --iso 200,800 --color-field velocity " CAM},
    {"jet_iso_translucent", kJet,
     "{DATA} --field pressure --tf cool-warm --range -3000,1000 --opacity -3000:0.2,0:0,1000:0.2 --iso -500 "
     "--iso-alpha 0.5 --color-field velocity " CAM},
    {"jet_shade", kJet, "{DATA} --step 1 --shade " CAM},
    {"jet_ortho", kJet, "{DATA} --step 1 --ortho " CAM},
    {"jet_spp4", kJet, "{DATA} --step 1 --spp 4 " CAM},
    {"jet_noskip_noadaptive", kJet, "{DATA} --step 1 --no-skip --no-adaptive --rate 1 " CAM},
    {"jet_nojitter_white", kJet, "{DATA} --step 1 --no-jitter --background 1,1,1 " CAM},
    {"jet_alpha_premultiplied", kJet, "{DATA} --step 1 --alpha " CAM},
    {"jet_blocks_nearest", kJet, "{DATA} --step 1 --integrator blocks --reconstruction nearest " CAM},
    {"jet_blocks_trilinear", kJet, "{DATA} --step 1 --integrator blocks --reconstruction trilinear " CAM},
    {"cosmo_dvr", kCosmo, "{DATA} --size 80x64"},
    {"cosmo_blackbody", kCosmo, "{DATA} --optics blackbody --size 80x64"},
    {"cosmo_blackbody_linear_nearest", kCosmo,
     "{DATA} --optics blackbody --density-scale linear --reconstruction nearest --size 80x64"},
    {"cosmo_blocks_log", kCosmo, "{DATA} --integrator blocks --field density --log --size 80x64"},
    {"cosmo_demo_blackbody", "", "--demo cosmo --cells 3e4 --optics blackbody --size 80x64"},
    {"plotfile_dvr", kPlotfile, "{DATA} --field density --size 80x64"},
    {"plotfile_iso_shade", kPlotfile, "{DATA} --field temp --iso 1500 --color-field density --shade --size 80x64"},
    {"plotfile_blocks_log", kPlotfile, "{DATA} --field temp --integrator blocks --log --size 80x64"},
};
#undef CAM

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// A path as one shell word.
std::string shell_quoted(const fs::path& p) {
  std::string quoted = "'";  // appended, not "'" + ...: GCC 12 warns falsely (-Wrestrict) on that
  quoted += replace_all(p.string(), "'", "'\\''");
  quoted += "'";
  return quoted;
}

std::string volstream_bin() {
  const char* env = std::getenv("VOLSTREAM_GOLDEN_BIN");
  return env && *env ? std::string(env) : std::string(VOLSTREAM_BIN);
}

std::string python() { return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3"; }

std::string read_text(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs a shell command with stdout and stderr to `log`; "" on success, else a message with the log.
std::string run(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " >" + shell_quoted(log) + " 2>&1").c_str());
  if (status == 0) return "";
  return "command failed (status " + std::to_string(status) + "): " + command + "\n" + read_text(log);
}

// Datasets already made in this process, by command (each case's scratch dir is kept until it reruns).
std::map<std::string, fs::path>& datasets() {
  static std::map<std::string, fs::path> made;
  return made;
}

class GoldenImages : public ::testing::TestWithParam<Case> {};

// The cosmo demo refines where its float expressions land, and g++ and clang round them
// differently (1e5 cells: 99,938 with g++ 12 -O3, 99,945 with clang 14 -O2), so its datasets,
// and the images of them, are only comparable with the g++ build that made the references.
[[maybe_unused]] bool uses_cosmo_demo(const Case& c) {
  return std::string(c.dataset) == kCosmo || std::string(c.args).find("--demo cosmo") != std::string::npos;
}

TEST_P(GoldenImages, MatchesReference) {
  const Case& c = GetParam();
#if defined(__clang__)
  if (uses_cosmo_demo(c)) GTEST_SKIP() << "the cosmo demo's data depend on the compiler; references made with g++";
#endif
  const fs::path golden = fs::path(VOLSTREAM_SOURCE_DIR) / "tests" / "golden" / (std::string(c.name) + ".pfm");
  ASSERT_TRUE(fs::exists(golden)) << "missing reference " << golden;
  const fs::path dir = vs::test::scratch_dir(c.name);
  const std::string vs_bin = shell_quoted(volstream_bin());

  std::string args = c.args;
  if (*c.dataset) {
    auto it = datasets().find(c.dataset);
    if (it == datasets().end() || !fs::exists(it->second / "manifest.json")) {
      const fs::path data = dir / "data";
      std::string cmd = replace_all(c.dataset, "{VS}", vs_bin);
      cmd = replace_all(cmd, "{PY}", python());
      cmd = replace_all(cmd, "{SRC}", shell_quoted(VOLSTREAM_SOURCE_DIR));
      cmd = replace_all(cmd, "{DIR}", shell_quoted(data));
      const std::string err = run(cmd, dir / "dataset.log");
      ASSERT_EQ(err, "");
      it = datasets().insert_or_assign(c.dataset, data).first;
    }
    args = replace_all(args, "{DATA}", shell_quoted(it->second));
  }
  const fs::path out = dir / (std::string(c.name) + ".pfm");
  const std::string err = run(vs_bin + " render " + args + " -o " + shell_quoted(out), dir / "render.log");
  ASSERT_EQ(err, "");

  const vs::Image want = vs::read_pfm(golden.string());
  const vs::Image got = vs::read_pfm(out.string());
  ASSERT_EQ(got.width, want.width);
  ASSERT_EQ(got.height, want.height);
  ASSERT_EQ(got.rgba.size(), want.rgba.size());
  float max_diff = 0;
  size_t worst = 0, first_bad = 0, over = 0;
  for (size_t i = 0; i < want.rgba.size(); ++i) {
    const float d = std::fabs(got.rgba[i] - want.rgba[i]);
    if (!(d <= kTolerance) && over++ == 0) first_bad = i;  // NaN counts as over
    if (!(d <= max_diff)) max_diff = d, worst = i;         // a NaN sticks, and fails below
  }
  const size_t px = worst / 4;
  std::printf("[ golden   ] %-32s max abs diff %.3g (pixel %zu,%zu channel %zu), %zu values over %.0e\n", c.name,
              double(max_diff), px % want.width, px / want.width, worst % 4, over, double(kTolerance));
  EXPECT_LE(over, kStrayValuesAllowed) << c.name << ": max abs diff " << max_diff
                                       << "; first value over the tolerance: pixel (" << first_bad / 4 % want.width
                                       << ", " << first_bad / 4 / want.width << ") channel " << first_bad % 4
                                       << ": got " << got.rgba[first_bad] << ", want " << want.rgba[first_bad]
                                       << "; new image " << out << ", reference " << golden;
  EXPECT_LE(max_diff, over ? kStrayTolerance : kTolerance) << c.name;
}

INSTANTIATE_TEST_SUITE_P(Golden, GoldenImages, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           return std::string(param_info.param.name);
                         });

}  // namespace
