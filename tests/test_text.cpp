// The small text helpers the command line and the results rely on.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "oovr/core/text.h"

namespace oovr {
namespace {

TEST(Text, SplitListDropsEmptyItems) {
  EXPECT_EQ(split_list("a,b,,c"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(split_list("").empty());
  EXPECT_TRUE(split_list(",,").empty());
}

TEST(Text, SplitFieldsKeepsEmptyFields) {
  EXPECT_EQ(split_fields("a,b,,c", ','), (std::vector<std::string>{"a", "b", "", "c"}));
  EXPECT_EQ(split_fields("", ','), (std::vector<std::string>{""}));
  EXPECT_EQ(split_fields(",", ','), (std::vector<std::string>{"", ""}));
  EXPECT_EQ(split_fields("x\ny\n", '\n'), (std::vector<std::string>{"x", "y", ""}));
}

TEST(Text, WholeNumbersAreDigitsOnlyAndInRange) {
  EXPECT_EQ(parse_whole_number("12", 1, 100), 12u);
  for (const char* bad : {" 12", "+12", "-5", "1e3", "12MB", "", "101", "0"})
    EXPECT_FALSE(parse_whole_number(bad, 1, 100).has_value()) << "'" << bad << "'";
  EXPECT_FALSE(parse_whole_number("99999999999999999999999", 1, UINT64_MAX).has_value()) << "overflow";
}

// The command line a result records reads back, through a POSIX shell, as
// the words that were given.
TEST(Text, CommandLinesAreQuotedAsAShellReadsThem) {
  const char* plain[] = {"oovr", "compare", "--scene", "oa:oa_dm4", "--set", "link.bandwidth=64GBps", "--json", "out/r.json"};
  EXPECT_EQ(shell_command_line(8, plain), "oovr compare --scene oa:oa_dm4 --set link.bandwidth=64GBps --json out/r.json");
  const char* odd[] = {"oovr", "--set", "link.bandwidth=1 TBps", "", "it's", "$HOME", "a;b"};
  EXPECT_EQ(shell_command_line(7, odd), "oovr --set 'link.bandwidth=1 TBps' '' 'it'\\''s' '$HOME' 'a;b'");
}

// Text written into a Markdown document or a CSV file (`oovr paper`'s
// machine table and paper-against.md, claims-against.csv): a file name
// cannot end a cell, open a link or a tag, or split a field.
TEST(Text, MarkdownAndCsvFieldsHoldAnyTextAsText) {
  EXPECT_EQ(markdown_text("experiments/paper.toml:3"), "experiments/paper.toml:3");
  EXPECT_EQ(markdown_text("a|b"), "a\\|b");
  EXPECT_EQ(markdown_text("[x](javascript:y) <img src=z> `c` *d* _e_ &amp; ~f~ ![g]"),
            "\\[x\\](javascript:y) \\<img src=z\\> \\`c\\` \\*d\\* \\_e\\_ \\&amp; \\~f\\~ \\!\\[g\\]");
  EXPECT_EQ(markdown_text("back\\slash"), "back\\\\slash");
  EXPECT_EQ(markdown_text("two\nlines\x1b[31m"), "two\\\\x0alines\\\\x1b\\[31m");  // printable, then escaped
  EXPECT_EQ(csv_field("crowd"), "crowd");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field(" padded"), "\" padded\"");
  EXPECT_EQ(csv_field("line\nbreak"), "line\\x0abreak");
}

}  // namespace
}  // namespace oovr
