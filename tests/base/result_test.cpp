#include "gport/base/result.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <variant>
#include <vector>

namespace gport {
namespace {

struct Problem {
    int code = 0;
    std::string message;
};

using IntResult = Result<int, Problem>;

IntResult half(int n) {
    if (n % 2 != 0) {
        return Problem{1, "odd"};
    }
    return n / 2;
}

TEST(Result, HoldsAValue) {
    const IntResult r = half(8);
    EXPECT_TRUE(r.has_value());
    EXPECT_TRUE(r.ok());
    EXPECT_TRUE(static_cast<bool>(r));
    EXPECT_EQ(r.value(), 4);
    EXPECT_EQ(*r, 4);
}

TEST(Result, HoldsAnError) {
    const IntResult r = half(7);
    EXPECT_FALSE(r.has_value());
    EXPECT_FALSE(r.ok());
    EXPECT_FALSE(static_cast<bool>(r));
    EXPECT_EQ(r.error().code, 1);
    EXPECT_EQ(r.error().message, "odd");
}

TEST(Result, UnexpectedMakesAnErrorExplicitly) {
    const IntResult r = unexpected(Problem{2, "explicit"});
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().message, "explicit");
}

TEST(Result, UnexpectedConvertsToTheErrorType) {
    const Result<int, std::string> r = unexpected("text");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error(), "text");
}

TEST(Result, ArrowReachesTheValue) {
    const Result<std::string, Problem> r = std::string("abc");
    EXPECT_EQ(r->size(), 3U);
    Result<std::vector<int>, Problem> v = std::vector<int>{1};
    v->push_back(2);
    EXPECT_EQ(v->size(), 2U);
}

TEST(Result, MovesOutMoveOnlyValues) {
    Result<std::unique_ptr<int>, Problem> r = std::make_unique<int>(5);
    std::unique_ptr<int> p = std::move(r).value();
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(*p, 5);
}

TEST(Result, MovesOutTheError) {
    Result<int, std::vector<std::string>> r = std::vector<std::string>{"a", "b"};
    ASSERT_FALSE(r.has_value());
    const std::vector<std::string> errors = std::move(r).error();
    EXPECT_EQ(errors.size(), 2U);
}

TEST(Result, ValueOrFallsBackOnlyOnError) {
    EXPECT_EQ(half(10).value_or(-1), 5);
    EXPECT_EQ(half(3).value_or(-1), -1);
}

TEST(Result, DoneSaysOnlyThatItWorked) {
    const Result<Done, Problem> done = Done{};
    EXPECT_TRUE(done);
    const Result<Done, Problem> failed = Problem{3, "no"};
    EXPECT_FALSE(failed);
}

TEST(Result, AskingForTheMissingSideIsAProgrammingError) {
    const IntResult value = half(2);
    const IntResult error = half(1);
    EXPECT_THROW(static_cast<void>(value.error()), std::bad_variant_access);
    EXPECT_THROW(static_cast<void>(error.value()), std::bad_variant_access);
}

TEST(Result, CopiesKeepTheirSide) {
    const IntResult a = half(6);
    const IntResult b = half(5);
    IntResult c = a;
    EXPECT_EQ(c.value(), 3);
    c = b;
    EXPECT_EQ(c.error().message, "odd");
}

}  // namespace
}  // namespace gport
