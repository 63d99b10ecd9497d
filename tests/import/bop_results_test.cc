// The BOP results CSV reader reads the file in chunks (src/import/
// bop_results.cc): rows across a chunk boundary, a line longer than a
// chunk, CRLF and a last line without '\n' read as when the file was read
// whole, with the same line numbers.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "import/bop_files.h"

namespace symba::import_internal {
namespace {

namespace fs = std::filesystem;

std::string WriteFile(const std::string& name, const std::string& text) {
  const std::string path = (fs::path(::testing::TempDir()) / name).string();
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string Row(int im_id, int obj_id) {
  return "3," + std::to_string(im_id) + "," + std::to_string(obj_id) +
         ",0.5,1 0 0 0 1 0 0 0 1,10 20 " + std::to_string(1000 + im_id) +
         ",0.1";
}

TEST(ReadBopResults, RowsAcrossChunksKeepTheirLineNumbers) {
  // ~2.4 MB: the 1 MB chunks end inside rows.
  std::string text = "scene_id,im_id,obj_id,score,R,t,time\n";
  const int n = 50000;
  for (int i = 0; i < n; ++i) text += Row(i, i % 7 + 1) + "\n";
  std::vector<BopResultRow> rows;
  ASSERT_TRUE(ReadBopResults(WriteFile("chunks.csv", text), {}, &rows).ok());
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; i += 997) {
    EXPECT_EQ(rows[i].im_id, i);
    EXPECT_EQ(rows[i].obj_id, i % 7 + 1);
    EXPECT_EQ(rows[i].line, i + 2);
    EXPECT_DOUBLE_EQ(rows[i].T_co.t.z(), (1000 + i) / 1000.0);
  }
}

TEST(ReadBopResults, ALineLongerThanAChunkCrlfAndNoLastNewline) {
  const std::string blank(3 << 20, ' ');  // 3 MB of spaces: a blank line
  const std::string text =
      Row(0, 1) + "\r\n" + blank + "\r\n" + Row(1, 2) + "\r\n" + Row(2, 3);
  const std::string path = WriteFile("long_line.csv", text);
  std::vector<BopResultRow> rows;
  ASSERT_TRUE(ReadBopResults(path, {}, &rows).ok());
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].line, 3);
  EXPECT_EQ(rows[2].line, 4);
  EXPECT_EQ(rows[2].obj_id, 3);

  const std::string bad = WriteFile("long_line_bad.csv", blank + "\n7,x\n");
  EXPECT_EQ(ReadBopResults(bad, {}, &rows).message(),
            bad +
                ":2: expected 7 comma-separated fields "
                "(scene_id,im_id,obj_id,score,R,t,time), got 2");
}

TEST(ReadBopResults, AMissingFileCannotBeOpened) {
  const std::string path =
      (fs::path(::testing::TempDir()) / "none.csv").string();
  std::vector<BopResultRow> rows;
  EXPECT_EQ(ReadBopResults(path, {}, &rows).message(), path + ": cannot open");
}

}  // namespace
}  // namespace symba::import_internal
