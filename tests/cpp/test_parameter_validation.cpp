// User-facing parameter checks (ModelNames.hpp, Validation.hpp): a bad value is rejected with a
// std::invalid_argument (a Python ValueError) naming the parameter, the value and what is allowed.
#include "viscbridge/physics/ModelNames.hpp"
#include "viscbridge/physics/NormalViscous.hpp"
#include "viscbridge/physics/TangentialViscous.hpp"
#include "viscbridge/physics/Validation.hpp"
#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <string>

using namespace viscbridge;

namespace {
// The message of the std::invalid_argument thrown by f, or "" if it did not throw one.
template <class F> std::string rejection(F&& f)
{
	try {
		f();
	} catch (const std::invalid_argument& e) {
		return e.what();
	}
	return "";
}

void expectContainsAll(const std::string& message, std::initializer_list<const char*> parts)
{
	EXPECT_FALSE(message.empty()) << "did not throw std::invalid_argument";
	for (const char* part : parts) EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' missing from: " << message;
}
} // namespace

// Known names map to their enum values, in the documented order.
TEST(ModelNames, KnownNamesParseToTheirEnums)
{
	EXPECT_EQ(parseName("Ip2", "normal", "none", normalModelNames), static_cast<int>(NormalModel::none));
	EXPECT_EQ(parseName("Ip2", "normal", "adamsPerchard", normalModelNames), static_cast<int>(NormalModel::adamsPerchard));
	EXPECT_EQ(parseName("Ip2", "normal", "pitois", normalModelNames), static_cast<int>(NormalModel::pitois));
	EXPECT_EQ(parseName("Ip2", "tangential", "none", tangentialModelNames), static_cast<int>(TangentialModel::none));
	EXPECT_EQ(parseName("Ip2", "tangential", "washino", tangentialModelNames), static_cast<int>(TangentialModel::washino));
	EXPECT_EQ(parseName("Ip2", "tangential", "slip", tangentialModelNames), static_cast<int>(TangentialModel::slip));
	EXPECT_EQ(parseName("Ip2", "tangential", "goldman", tangentialModelNames), static_cast<int>(TangentialModel::goldman));
	EXPECT_EQ(parseName("Law2", "integration", "explicit", integrationNames), static_cast<int>(Integration::explicitEuler));
	EXPECT_EQ(parseName("Law2", "integration", "implicit", integrationNames), static_cast<int>(Integration::implicitEuler));
}

// The names the model structs carry are the parsable ones.
TEST(ModelNames, StructNamesAreListed)
{
	EXPECT_EQ(parseName("x", "normal", AdamsPerchard::name, normalModelNames), 1);
	EXPECT_EQ(parseName("x", "normal", Pitois::name, normalModelNames), 2);
	EXPECT_EQ(parseName("x", "tangential", WashinoTangential::name, tangentialModelNames), 1);
	EXPECT_EQ(parseName("x", "tangential", SlipTangential::name, tangentialModelNames), 2);
	EXPECT_EQ(parseName("x", "tangential", GoldmanTangential::name, tangentialModelNames), 3);
}

// Unknown (also wrongly capitalised) names: the message names owner.parameter, the bad value and
// every allowed name.
TEST(ModelNames, UnknownNameIsRejectedWithParameterValueAndAllowedNames)
{
	const std::string m = rejection([] { parseName("Ip2_ViscBridge", "normalModel", "adamsperchard", normalModelNames); });
	expectContainsAll(m, { "Ip2_ViscBridge.normalModel", "'adamsperchard'", "'none'", "'adamsPerchard'", "'pitois'" });
	const std::string t = rejection([] { parseName("Ip2_ViscBridge", "tangentialModel", "goldmann", tangentialModelNames); });
	expectContainsAll(t, { "tangentialModel", "goldmann", "'none', 'washino', 'slip', 'goldman'" });
	EXPECT_FALSE(rejection([] { parseName("Law2", "integration", "", integrationNames); }).empty());
}

// requirePositive: > 0 and finite.
TEST(Validation, RequirePositive)
{
	EXPECT_TRUE(rejection([] { requirePositive("Ip2", "viscosity", 1e-3); }).empty());
	expectContainsAll(rejection([] { requirePositive("Ip2", "viscosity", -2.5); }), { "Ip2.viscosity", "-2.5", "> 0" });
	expectContainsAll(rejection([] { requirePositive("Ip2", "viscosity", 0.0); }), { "viscosity", "=0 ", "> 0" });
	EXPECT_FALSE(rejection([] { requirePositive("Ip2", "viscosity", std::numeric_limits<double>::infinity()); }).empty());
	EXPECT_FALSE(rejection([] { requirePositive("Ip2", "viscosity", std::nan("")); }).empty());
}

// requireNonNegative: ≥ 0 and finite; the meaning of zero is appended to the allowed range.
TEST(Validation, RequireNonNegative)
{
	EXPECT_TRUE(rejection([] { requireNonNegative("Ip2", "formationDistance", 0.0); }).empty());
	expectContainsAll(rejection([] { requireNonNegative("Ip2", "formationDistance", -1e-6, " (0: at contact)"); }),
	                  { "formationDistance", "-1e-06", ">= 0", "0: at contact" });
	EXPECT_FALSE(rejection([] { requireNonNegative("Ip2", "formationDistance", std::nan("")); }).empty());
}

// requireInRange: open/closed ends as asked, the range written as an interval in the message.
TEST(Validation, RequireInRange)
{
	const auto check = [](double v) { requireInRange("Ip2", "sMinRel", v, 0.0, true, 1.0, false); }; // (0, 1]
	EXPECT_TRUE(rejection([&] { check(1.0); }).empty());
	EXPECT_TRUE(rejection([&] { check(1e-300); }).empty());
	expectContainsAll(rejection([&] { check(0.0); }), { "Ip2.sMinRel", "=0 ", "(0, 1]" });
	expectContainsAll(rejection([&] { check(1.5); }), { "sMinRel", "1.5", "(0, 1]" });
	expectContainsAll(rejection([] { requireInRange("Ip2", "contactAngle", 2.0, 0.0, false, 1.5707963267948966, true); }),
	                  { "contactAngle", "=2 ", "[0, 1.570796327)" });
	EXPECT_TRUE(rejection([] { requireInRange("Ip2", "contactAngle", 0.0, 0.0, false, 1.5707963267948966, true); }).empty());
	EXPECT_FALSE(rejection([&] { check(std::nan("")); }).empty());
}

TEST(Validation, RequireFinite)
{
	EXPECT_TRUE(rejection([] { requireFinite("Law2", "dt", -3.0, "finite"); }).empty());
	expectContainsAll(rejection([] { requireFinite("Law2", "dt", -std::numeric_limits<double>::infinity(), "finite"); }), { "Law2.dt", "-inf", "finite" });
}
