#include "gport/base/json_depth.hpp"

#include <gtest/gtest.h>

#include <string>

namespace gport::base {
namespace {

std::string nested(std::size_t levels) {
    return std::string(levels, '[') + std::string(levels, ']');
}

TEST(JsonDepth, AtTheLimitIsAcceptedAndOneLevelMoreIsNot) {
    EXPECT_FALSE(nested_deeper_than(nested(64), 64));
    EXPECT_TRUE(nested_deeper_than(nested(65), 64));
    EXPECT_FALSE(nested_deeper_than(R"({"a":{"b":[1,{"c":2}]}})", 4));
    EXPECT_TRUE(nested_deeper_than(R"({"a":{"b":[1,{"c":2}]}})", 3));
}

TEST(JsonDepth, BracketsInStringsDoNotCountNorDoEscapedQuotesEndThem) {
    EXPECT_FALSE(nested_deeper_than(R"({"a":"[[[[{{{{"})", 1));
    EXPECT_FALSE(nested_deeper_than(R"({"a":"\"[[[[\\"})", 1));
    // The string ends at the unescaped quote; the brackets after it count.
    EXPECT_TRUE(nested_deeper_than(R"({"a":"\\",[[1]]})", 2));
}

TEST(JsonDepth, ClosingsWithNothingOpenCannotHideADeepRun) {
    EXPECT_TRUE(nested_deeper_than("]]]]]]" + nested(3), 2));
    EXPECT_FALSE(nested_deeper_than("", 0));
}

static_assert(nested_deeper_than("[[[]]]", 2));
static_assert(!nested_deeper_than("[[[]]]", 3));

}  // namespace
}  // namespace gport::base
