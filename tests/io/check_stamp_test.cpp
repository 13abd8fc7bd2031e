// Check stamps (io/check_stamp.h): a check is remembered only for the files exactly as it read
// them, and a mesh dataset changed after its checks passed is checked again and refused: in
// place (same size, same inode), for either encoding and for the walk records checked at the
// first walk.
#include "volstream/io/check_stamp.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include "test_util.h"
#include "volstream/backend/launch_times.h"
#include "volstream/core/error.h"
#include "volstream/io/dataset.h"
#include "volstream/io/mesh_convert.h"

namespace vs {
namespace {
namespace fs = std::filesystem;

// Stamps in a directory of the test's own, restored afterwards.
class StampDirectory {
 public:
  explicit StampDirectory(const fs::path& dir) {
    if (const char* old = std::getenv("VOLSTREAM_CHECK_STAMPS")) old_ = old;
    setenv("VOLSTREAM_CHECK_STAMPS", dir.c_str(), 1);
  }
  ~StampDirectory() {
    old_.empty() ? unsetenv("VOLSTREAM_CHECK_STAMPS") : setenv("VOLSTREAM_CHECK_STAMPS", old_.c_str(), 1);
  }

 private:
  std::string old_;
};

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// Overwrites bytes in place: the same file (inode) and size, other contents.
void overwrite(const fs::path& path, uint64_t offset, const std::string& bytes) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(std::streamoff(offset));
  f.write(bytes.data(), std::streamsize(bytes.size()));
  ASSERT_TRUE(f.good()) << path;
}

void wait_until_settled() { std::this_thread::sleep_for(std::chrono::duration<double>(kSettleSeconds + 0.2)); }

TEST(CheckStamp, RemembersACheckUntilAFileChanges) {
  const fs::path dir = test::scratch_dir("check_stamp_files");
  const StampDirectory stamps(dir / "stamps");
  const fs::path a = dir / "a.bin", b = dir / "b.bin";
  write_text(a, "first file");
  write_text(b, "second file");

  // Files changed within the settle time are not stamped (a change in the same clock tick could
  // keep their times).
  CheckStamp("test check", {a, b}).record();
  EXPECT_FALSE(CheckStamp("test check", {a, b}).passed_before());

  wait_until_settled();
  CheckStamp("test check", {a, b}).record();
  EXPECT_TRUE(CheckStamp("test check", {a, b}).passed_before());
  EXPECT_FALSE(CheckStamp("another check", {a, b}).passed_before());
  EXPECT_FALSE(CheckStamp("test check", {a}).passed_before());

  // A stamp another user could have written is not trusted.
  const fs::path stamp = CheckStamp("test check", {a, b}).path();
  ASSERT_FALSE(stamp.empty());
  ASSERT_EQ(::chmod(stamp.c_str(), 0620), 0);
  EXPECT_FALSE(CheckStamp("test check", {a, b}).passed_before());
  ASSERT_EQ(::chmod(stamp.c_str(), 0600), 0);
  EXPECT_TRUE(CheckStamp("test check", {a, b}).passed_before());

  overwrite(b, 0, "S");  // same size, same inode
  EXPECT_FALSE(CheckStamp("test check", {a, b}).passed_before());
  // Changed just now: not stamped again until it settles.
  CheckStamp("test check", {a, b}).record();
  EXPECT_FALSE(CheckStamp("test check", {a, b}).passed_before());
}

// Writing a stamp removes those not written for 30 days, and keeps the others.
TEST(CheckStamp, WritingOneRemovesStaleStamps) {
  const fs::path dir = test::scratch_dir("check_stamp_stale");
  const StampDirectory stamps(dir / "stamps");
  fs::create_directories(dir / "stamps");
  write_text(dir / "stamps" / "old", "an old build's stamp");
  write_text(dir / "stamps" / "recent", "a stamp of last week");
  const auto now = fs::file_time_type::clock::now();
  fs::last_write_time(dir / "stamps" / "old", now - std::chrono::hours(24 * 31));
  fs::last_write_time(dir / "stamps" / "recent", now - std::chrono::hours(24 * 7));
  write_text(dir / "a.bin", "a");
  // A settled file, as stamps are written only for those.
  fs::last_write_time(dir / "a.bin", now - std::chrono::hours(1));
  const CheckStamp unsettled("test check", {dir / "a.bin"});  // its ctime is still new
  unsettled.record();
  EXPECT_TRUE(fs::exists(dir / "stamps" / "old")) << "nothing is written for an unsettled file, nor removed";
  wait_until_settled();
  CheckStamp("test check", {dir / "a.bin"}).record();
  EXPECT_TRUE(CheckStamp("test check", {dir / "a.bin"}).passed_before());
  EXPECT_FALSE(fs::exists(dir / "stamps" / "old"));
  EXPECT_TRUE(fs::exists(dir / "stamps" / "recent"));
}

TEST(CheckStamp, OffStampsNothing) {
  const fs::path dir = test::scratch_dir("check_stamp_off");
  const StampDirectory stamps("off");
  write_text(dir / "a.bin", "a");
  const CheckStamp stamp("test check", {dir / "a.bin"});
  EXPECT_TRUE(stamp.path().empty());
  stamp.record();
  EXPECT_FALSE(stamp.passed_before());
  EXPECT_TRUE(check_stamp_directory().empty());
}

bool launched(const char* name) {
  for (const LaunchTime& t : launch_times().snapshot())
    if (t.name == name) return true;
  return false;
}

fs::path convert_demo(const char* shape, MeshEncoding encoding, const char* name) {
  const fs::path d = test::scratch_dir(name);
  auto series = make_mesh_demo_series({shape, 3000, 1});
  ConvertOptions options = ConvertOptions::silent();
  options.mesh_encoding = encoding;
  convert_mesh_to_dataset(*series, d, options);
  return d;
}

// The walk records as the first CPU walk asks for them (checked, or through their stamp).
void take_walk_records(const Dataset& ds) {
  const MeshAccel& accel = ds.mesh_accel();
  ASSERT_TRUE(accel.stored_tet_walk);
  accel.stored_tet_walk(ds.mesh(), accel.neighbors);
}

TEST(CheckStamp, AMeshChangedAfterItsChecksIsCheckedAgain) {
  const fs::path dir = test::scratch_dir("check_stamp_meshes");
  const StampDirectory stamps(dir / "stamps");
  const fs::path reference = convert_demo("tets", MeshEncoding::reference, "check_stamp_reference");
  const fs::path compact = convert_demo("tets", MeshEncoding::compact, "check_stamp_compact");
  wait_until_settled();
  for (const fs::path& d : {reference, compact}) {
    launch_times().clear();
    const Dataset first(d);
    EXPECT_FALSE(launched("mesh checked before (stamp)")) << d;
    const Dataset again(d);
    EXPECT_TRUE(launched("mesh checked before (stamp)")) << d;
  }
  launch_times().clear();
  take_walk_records(Dataset(reference));
  EXPECT_FALSE(launched("stored tet walk records (stamp)"));
  take_walk_records(Dataset(reference));
  EXPECT_TRUE(launched("stored tet walk records (stamp)"));

  // A walk record's neighbour changed in place: refused at the first walk.
  overwrite(reference / "mesh_tet_walk.bin", offsetof(TetWalkRecord, neighbor), std::string(4, '\0'));
  EXPECT_NE(test::input_error_line([&] { take_walk_records(Dataset(reference)); }), "accepted");
  // An element's corner out of range, and a compact leaf record overwritten: refused at open.
  overwrite(reference / "mesh_elements.bin", 0, std::string(4, '\xff'));
  EXPECT_NE(test::input_error_line([&] { Dataset ds(reference); }), "accepted");
  overwrite(compact / "compact_leaves.bin", 0, std::string(16, '\xff'));
  EXPECT_NE(test::input_error_line([&] { Dataset ds(compact); }), "accepted");
}

}  // namespace
}  // namespace vs
