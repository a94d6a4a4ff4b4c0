// Output transactions (errormodel/atomic_file.h): the files of one command appear together or
// not at all; a failed stage or rename leaves neither the set nor temporaries behind.
#include "vcmm/errormodel/atomic_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace {

namespace fs = std::filesystem;
using vcmm::errormodel::check_output_path;
using vcmm::errormodel::OutputError;
using vcmm::errormodel::OutputTransaction;
using vcmm::errormodel::write_file_atomically;

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() /
                     ("vcmm_atomic_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t entries(const fs::path& d) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(d), fs::directory_iterator()));
}

TEST(OutputTransaction, AllFilesAppearTogetherOnCommit) {
  const fs::path d = fresh_dir("commit");
  write_file_atomically((d / "a.txt").string(), "old a");
  OutputTransaction t;
  t.stage((d / "a.txt").string(), "new a");
  t.stage((d / "b.txt").string(), "new b");
  EXPECT_EQ(slurp(d / "a.txt"), "old a");  // nothing visible before the commit
  EXPECT_FALSE(fs::exists(d / "b.txt"));
  t.commit();
  EXPECT_EQ(slurp(d / "a.txt"), "new a");
  EXPECT_EQ(slurp(d / "b.txt"), "new b");
  EXPECT_EQ(entries(d), 2u);  // no temporaries or backups left
  fs::remove_all(d);
}

TEST(OutputTransaction, AFailingStageWritesNothing) {
  const fs::path d = fresh_dir("stage");
  try {
    OutputTransaction t;
    t.stage((d / "report.txt").string(), "report");
    t.stage((d / "missing" / "samples.csv").string(), "samples");
    t.commit();
    FAIL() << "a stage into a missing directory must throw";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("samples.csv"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(entries(d), 0u);  // neither the report nor its temporary
  fs::remove_all(d);
}

TEST(OutputTransaction, UncommittedTransactionRemovesItsTemporaries) {
  const fs::path d = fresh_dir("discard");
  {
    OutputTransaction t;
    t.stage((d / "a.txt").string(), "a");
    EXPECT_EQ(entries(d), 1u);  // the temporary
  }
  EXPECT_EQ(entries(d), 0u);
  fs::remove_all(d);
}

TEST(OutputTransaction, AFailedRenameRollsBackTheFilesAlreadyMoved) {
  const fs::path d = fresh_dir("rollback");
  write_file_atomically((d / "a.txt").string(), "old a");
  OutputTransaction t;
  t.stage((d / "a.txt").string(), "new a");
  t.stage((d / "new.txt").string(), "new");
  t.stage((d / "b.txt").string(), "new b");
  fs::create_directories(d / "b.txt" / "blocker");  // renaming a file over it must fail
  EXPECT_THROW(t.commit(), OutputError);
  EXPECT_EQ(slurp(d / "a.txt"), "old a");  // restored
  EXPECT_FALSE(fs::exists(d / "new.txt"));  // removed: it did not exist before
  EXPECT_TRUE(fs::is_directory(d / "b.txt"));
  EXPECT_EQ(entries(d), 2u);  // a.txt and the blocking directory only
  fs::remove_all(d);
}

TEST(OutputTransaction, TheSameTargetTwiceAndNonRegularTargetsAreRefused) {
  const fs::path d = fresh_dir("same");
  OutputTransaction t;
  t.stage((d / "x.csv").string(), "1");
  EXPECT_THROW(t.stage((d / "." / "x.csv").string(), "2"), OutputError);
  EXPECT_THROW(t.stage("/dev/null", "3"), OutputError);
  EXPECT_THROW(t.stage(d.string(), "4"), OutputError);
  t.discard();
  EXPECT_EQ(entries(d), 0u);
  EXPECT_TRUE(fs::exists("/dev/null") && !fs::is_regular_file("/dev/null"));
  fs::remove_all(d);
}

TEST(OutputTransaction, PreflightNamesThePathAndTheReason) {
  const fs::path d = fresh_dir("preflight");
  write_file_atomically((d / "file").string(), "x");
  EXPECT_NO_THROW(check_output_path((d / "ok.json").string()));
  EXPECT_NO_THROW(check_output_path((d / "file").string()));  // replaced later: allowed
  auto message = [](const std::string& p) {
    try {
      check_output_path(p);
    } catch (const OutputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message((d / "nodir" / "r.json").string()).find("does not exist"), std::string::npos);
  EXPECT_NE(message((d / "file" / "r.json").string()).find("is not a directory"), std::string::npos);
  EXPECT_NE(message("/dev/null").find("not a regular file"), std::string::npos);
  EXPECT_NE(message(d.string()).find("not a regular file"), std::string::npos);
  EXPECT_NE(message("").find("empty"), std::string::npos);
  fs::remove_all(d);
}

}  // namespace
