#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "io/expression.hpp"

namespace biofsi {
namespace {

const double kPi = std::acos(-1.0);
const double kTol = 8 * std::numeric_limits<double>::epsilon();

const std::vector<std::array<double, 4>> kPoints = {{0, 0, 0, 0},
                                                    {1.25, -3.5, 0.05, 2},
                                                    {-5, 5, -0.1, 1e3},
                                                    {2.5, -2.5, 0.1, 0.5},
                                                    {3.7, 1.1, 0, 7}};

std::string message_of(const std::string& text) {
  try {
    Expression e(text);
  } catch (const std::invalid_argument& err) {
    return err.what();
  }
  ADD_FAILURE() << "'" << text << "' was accepted";
  return "";
}

TEST(Expression, EvaluatesThePapersCosineInletProfile) {
  Expression e("0.5 + 0.5*cos(0.2*_pi*x)");
  for (const auto& p : kPoints)
    EXPECT_NEAR(e(p[0], p[1], p[2], p[3]), 0.5 + 0.5 * std::cos(0.2 * kPi * p[0]), kTol);
  EXPECT_FALSE(e.is_constant());
}

TEST(Expression, EvaluatesThePapersBracketedProductWithImplicitMultiplication) {
  Expression e("[0.5+0.5cos(0.2 pi x)][1+cos(0.05 pi y + 1.25 pi)]");
  for (const auto& p : kPoints) {
    const double expected =
        (0.5 + 0.5 * std::cos(0.2 * kPi * p[0])) * (1 + std::cos(0.05 * kPi * p[1] + 1.25 * kPi));
    EXPECT_NEAR(e(p[0], p[1], p[2], p[3]), expected, kTol) << p[0] << " " << p[1];
  }
  EXPECT_EQ(e.text(), "[0.5+0.5cos(0.2 pi x)][1+cos(0.05 pi y + 1.25 pi)]");
}

TEST(Expression, ImplicitProductsKeepFunctionCallsAndPrecedence) {
  EXPECT_NEAR(Expression("2x y")(3, 4, 0, 0), 24, kTol);
  EXPECT_NEAR(Expression("2(x+1)")(3, 0, 0, 0), 8, kTol);
  EXPECT_NEAR(Expression("x(y+1)")(3, 1, 0, 0), 6, kTol);
  EXPECT_NEAR(Expression("(x)(y)")(3, 5, 0, 0), 15, kTol);
  EXPECT_NEAR(Expression("1 - 2x^2")(3, 0, 0, 0), -17, kTol);
  EXPECT_NEAR(Expression("1.5e-3 x")(2, 0, 0, 0), 3e-3, kTol);
  EXPECT_NEAR(Expression("sqrt(x)")(4, 0, 0, 0), 2, kTol);
  EXPECT_NEAR(Expression("min(x, y)")(4, 2, 0, 0), 2, kTol);
}

TEST(Expression, DefinesPiBesideMuparsersUnderscorePi) {
  EXPECT_NEAR(Expression("pi")(0, 0, 0, 0), kPi, kTol);
  // Exactly: muparser 2.3.3's own _pi has only 12 digits.
  EXPECT_EQ(Expression("_pi")(0, 0, 0, 0), kPi);
  EXPECT_EQ(Expression("pi")(0, 0, 0, 0), kPi);
  EXPECT_NEAR(Expression("cos(pi*x)")(1, 0, 0, 0), -1, kTol);
}

TEST(Expression, ReadsAllFourVariables) {
  Expression e("x + 10*y + 100*z + 1000*t");
  EXPECT_NEAR(e(1, 2, 3, 4), 4321, 1e-12);
  EXPECT_NEAR(e(-1, 0, 0, 0.5), 499, 1e-12);
}

TEST(Expression, KnowsWhetherItIsConstant) {
  EXPECT_TRUE(Expression("0").is_constant());
  EXPECT_TRUE(Expression("0.5 + 0.5*cos(0.2*_pi)").is_constant());
  EXPECT_FALSE(Expression("t").is_constant());
  EXPECT_FALSE(Expression("1 + 0*z").is_constant());
}

TEST(Expression, StillEvaluatesAfterMoves) {
  Expression a("x + 2*t");
  Expression b(std::move(a));
  EXPECT_NEAR(b(1, 0, 0, 3), 7, kTol);
  Expression c("0");
  c = std::move(b);
  EXPECT_NEAR(c(2, 0, 0, 1), 4, kTol);
  EXPECT_EQ(c.text(), "x + 2*t");
  // Reallocation moves every element: each must still see its own variables.
  std::vector<Expression> many;
  for (int i = 0; i < 40; ++i) many.emplace_back(std::to_string(i) + " + x*y");
  for (int i = 0; i < 40; ++i) EXPECT_NEAR(many[i](2, 3, 0, 0), i + 6, kTol);
}

TEST(Expression, RejectsSyntaxErrorsQuotingTheExpressionAndTheReason) {
  const std::string m = message_of("0.5 + * x");
  EXPECT_NE(m.find("'0.5 + * x'"), std::string::npos) << m;
  EXPECT_NE(m.find("nexpected"), std::string::npos) << m;  // muparser's "Unexpected operator"
  EXPECT_NE(message_of("cos(x").find("'cos(x'"), std::string::npos);
  EXPECT_NE(message_of("").find("''"), std::string::npos);
}

TEST(Expression, RejectsUnknownVariablesByName) {
  const std::string m = message_of("0.5 + 0.5*cos(0.2*pi*w)");
  EXPECT_NE(m.find("'0.5 + 0.5*cos(0.2*pi*w)'"), std::string::npos) << m;
  EXPECT_NE(m.find("unknown variable 'w'"), std::string::npos) << m;
  EXPECT_NE(message_of("X").find("unknown variable 'X'"), std::string::npos);
}

TEST(Expression, RejectsSeveralCommaSeparatedValues) {
  // "0,5" is a decimal comma in many locales; muparser would return the last value, 5.
  EXPECT_NE(message_of("0,5").find("comma"), std::string::npos);
}

// A value that is not finite throws where it is met, naming the key, the expression, the point
// and the time; finite values of the same expression pass through unchanged.
TEST(SpaceTimeFunction, ThrowsNamingKeyExpressionPointAndTimeForANonFiniteValue) {
  const auto f = space_time_function("1/(t-2)", "fields.scalar.boundary_conditions[0].value");
  EXPECT_EQ(f({0.5, 1, 0}, 1.0), -1.0);
  try {
    f({0.5, 1, 0}, 2.0);
    FAIL() << "no error at t = 2";
  } catch (const NonFiniteExpression& e) {
    EXPECT_STREQ(e.what(),
                 "fields.scalar.boundary_conditions[0].value: '1/(t-2)' is infinite at (x, y, z) "
                 "= (0.5, 1, 0), t = 2; expected an expression that is finite wherever it applies");
  }
  for (const char* text : {"sqrt(-1)", "1/(x-x)", "0/0", "10^400", "1/0"})
    EXPECT_THROW(space_time_function(text, "fields.scalar.initial")({0, 0, 0}, 0.0),
                 NonFiniteExpression)
        << text;
}

}  // namespace
}  // namespace biofsi
