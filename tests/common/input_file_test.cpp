#include "moreau/common/input_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "moreau/common/error.h"
#include "moreau/common/summary_json.h"

namespace moreau {
namespace {

namespace fs = std::filesystem;

// The message of the InputError that ReadInputFile(path) throws, or "" when it reads.
std::string Refusal(const std::string& path) {
  try {
    (void)ReadInputFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ReadInputFile, ReadsARegularFileWhole) {
  const fs::path path = fs::temp_directory_path() / ("moreau-input-" + std::to_string(getpid()));
  std::ofstream(path, std::ios::binary) << std::string("a\0b", 3);
  EXPECT_EQ(ReadInputFile(path.string()), std::string("a\0b", 3));
  EXPECT_EQ(NotAnInputFile(path.string()), "");
  try {
    (void)ReadInputFile(path.string(), 2);  // a bound below the size
    ADD_FAILURE() << "a file above the bound was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("the file has 3 bytes, more than the 2 accepted"),
              std::string::npos);
  }
  fs::remove(path);
}

TEST(ReadInputFile, RefusesWhatIsNotARegularFileWithoutReadingIt) {
  EXPECT_EQ(Refusal("/dev/zero"), "/dev/zero: is a character device, not a regular file");
  EXPECT_EQ(Refusal("/"), "/: is a directory");
  EXPECT_EQ(Refusal("/no/such/file"), "/no/such/file: does not exist");
  const fs::path fifo = fs::temp_directory_path() / ("moreau-fifo-" + std::to_string(getpid()));
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(Refusal(fifo.string()), fifo.string() + ": is a FIFO (named pipe), not a regular file");
  fs::remove(fifo);
}

TEST(WithoutByteOrderMark, DropsOnlyALeadingMark) {
  EXPECT_EQ(WithoutByteOrderMark("\xEF\xBB\xBFmarker"), "marker");
  EXPECT_EQ(WithoutByteOrderMark("marker\xEF\xBB\xBF"), "marker\xEF\xBB\xBF");
  EXPECT_EQ(WithoutByteOrderMark(""), "");
}

TEST(JsonText, ReplacesInvalidUtf8InsteadOfThrowing) {
  const nlohmann::json j = {{"label", std::string("R.\xFFhoulder")}};
  EXPECT_EQ(JsonText(j, -1), "{\"label\":\"R.\xEF\xBF\xBDhoulder\"}");
}

}  // namespace
}  // namespace moreau
