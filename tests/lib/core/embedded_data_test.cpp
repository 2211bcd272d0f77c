// The embedded numeric tables (CIE, Fresnel data) parse with the shared text helpers; a bad
// field is refused in one line naming the table and the line.
#include <gtest/gtest.h>

#include "core/embedded_data.hpp"
#include "glintscope/core/error.hpp"

namespace glintscope {
namespace {

TEST(EmbeddedData, TablesSkipCommentsAndTrimFields) {
    const NumericTable table = parse_numeric_table("# a comment\n lambda_nm , n,k\r\n400, 0.5 ,+3.25\n\n410,1e-1,2\n", "t.csv");
    EXPECT_EQ(table.columns, (std::vector<std::string>{"lambda_nm", "n", "k"}));
    ASSERT_EQ(table.rows.size(), 2u);
    EXPECT_EQ(table.rows[0], (std::vector<double>{400.0, 0.5, 3.25}));
    EXPECT_EQ(table.rows[1], (std::vector<double>{410.0, 0.1, 2.0}));
    EXPECT_EQ(table_comment("# a comment\n#   more\n1\n"), "a comment more");
}

TEST(EmbeddedData, ABadFieldIsOneLineNamingTheTableAndTheLine) {
    const auto error = [](std::string_view text) {
        try {
            parse_numeric_table(text, "data/materials/Al.csv");
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(error("a,b\n1,2\n3,x4\n"), "data/materials/Al.csv line 3: 'x4' is not a number");
    EXPECT_EQ(error("a,b\n1,inf\n"), "data/materials/Al.csv line 2: 'inf' is not finite");
    EXPECT_EQ(error("a,b\n1,2,3\n"), "data/materials/Al.csv line 2: expected 2 values, found 3");
    EXPECT_EQ(error("a,b\n"), "data/materials/Al.csv: the table has no rows");
}

}  // namespace
}  // namespace glintscope
