// Every file in tests/eds/corpus/bad/ is refused with the error its first
// line announces: `; expect: LINE: FRAGMENT` -> parse() says
// "NAME.eds:LINE: ..." containing FRAGMENT. No model, no exception, no crash.
#include <dirent.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "eds_reader.h"

namespace {

std::vector<std::string> bad_files() {
  std::vector<std::string> names;
  const std::string dir = std::string(MB2CO_EDS_CORPUS_DIR) + "/bad";
  if (DIR* d = opendir(dir.c_str())) {
    while (const dirent* e = readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > 4 && n.compare(n.size() - 4, 4, ".eds") == 0) names.push_back(n);
    }
    closedir(d);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST(EdsBadCorpus, EveryFileIsRefusedAtItsLineWithItsReason) {
  const std::vector<std::string> files = bad_files();
  ASSERT_GE(files.size(), 40u) << "the corpus is missing";
  for (const std::string& name : files) {
    SCOPED_TRACE(name);
    const std::string text = read_all(std::string(MB2CO_EDS_CORPUS_DIR) + "/bad/" + name);
    const std::string prefix = "; expect: ";
    ASSERT_EQ(text.compare(0, prefix.size(), prefix), 0) << "no expectation line";
    const size_t colon = text.find(": ", prefix.size());
    const size_t eol = text.find('\n');
    ASSERT_LT(colon, eol);
    const std::string line = text.substr(prefix.size(), colon - prefix.size());
    const std::string fragment = text.substr(colon + 2, eol - colon - 2);
    const mb2co::eds::ParseResult r = mb2co::eds::parse(text, name);
    ASSERT_FALSE(r) << "accepted";
    const std::string error = r.error.text();
    EXPECT_EQ(error.rfind(name + ":" + line + ": ", 0), 0u) << error;
    EXPECT_NE(error.find(fragment), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  }
}

TEST(EdsBadCorpus, EveryTruncationOfAGoodFileIsAModelOrAnError) {
  // A file cut anywhere (e.g. an interrupted download) never crashes or hangs
  // the reader; what it refuses it names with a line within the file.
  const std::string text = read_all(std::string(MB2CO_DOCS_DIR) + "/mb2co-ionode.eds");
  ASSERT_FALSE(text.empty());
  const int lines = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  for (size_t cut = 0; cut < text.size(); cut += 7) {
    const mb2co::eds::ParseResult r = mb2co::eds::parse(std::string_view(text).substr(0, cut), "cut.eds");
    if (!r) {
      EXPECT_GE(r.error.line, 1);
      EXPECT_LE(r.error.line, lines + 1);
    }
  }
}
