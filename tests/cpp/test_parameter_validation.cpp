// User-facing parameter checks (SubModels.hpp, BridgeParameters.hpp, Validation.hpp): a bad value is rejected with a
// std::invalid_argument (a Python ValueError) naming the parameter, the value and what is allowed.
#include "viscbridge/core/models/Parameters.hpp"
#include "viscbridge/core/pair/PairConstants.hpp"
#include "viscbridge/core/models/Registry.hpp"
#include "viscbridge/core/models/normal/NormalViscous.hpp"
#include "viscbridge/core/models/tangential/TangentialViscous.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include <cmath>
#include <gtest/gtest.h>
#include <limits>
#include <string>
#include <vector>

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

// Every registered model parses to its place in its slot's list; the first of a slot is 'none'.
template <class S> void expectEveryNameParses()
{
	for (std::size_t i = 0; i < S::Models::size; ++i)
		EXPECT_EQ(modelIndex<S>("Ip2", S::Models::names[i]), i) << S::parameter << " " << S::Models::names[i];
	EXPECT_STREQ(S::Models::names[0], "none");
	EXPECT_FALSE(S::Models::capabilities[0].enabled);
	EXPECT_NO_THROW(modelIndex<S>("Ip2", S::defaultModel));
}

TEST(Registry, EveryModelNameParsesToItsIndex)
{
	expectEveryNameParses<NormalSlot>();
	expectEveryNameParses<TangentialSlot>();
	expectEveryNameParses<DampingSlot>();
	expectEveryNameParses<CapillarySlot>();
	EXPECT_EQ(parseName("Law2", "integration", "explicit", integrationNames), static_cast<std::size_t>(Integration::explicitEuler));
	EXPECT_EQ(parseName("Law2", "integration", "implicit", integrationNames), static_cast<std::size_t>(Integration::implicitEuler));
}

// The names the model structs carry are the parsable ones.
TEST(Registry, StructNamesAreListed)
{
	EXPECT_EQ(modelIndex<NormalSlot>("x", AdamsPerchard::name), 1u);
	EXPECT_EQ(modelIndex<NormalSlot>("x", Pitois::name), 2u);
	EXPECT_EQ(modelIndex<TangentialSlot>("x", WashinoTangential::name), 1u);
	EXPECT_EQ(modelIndex<TangentialSlot>("x", SlipTangential::name), 2u);
	EXPECT_EQ(modelIndex<TangentialSlot>("x", GoldmanTangential::name), 3u);
	EXPECT_EQ(modelIndex<CapillarySlot>("x", WillettCapillary::name), 1u);
	EXPECT_EQ(modelIndex<CapillarySlot>("x", RabinovichCapillary::name), 2u);
}

// Unknown (also wrongly capitalised) names: the message names owner.parameter, the bad value and
// every allowed name.
TEST(Registry, UnknownNameIsRejectedWithParameterValueAndAllowedNames)
{
	const std::string m = rejection([] { modelIndex<NormalSlot>("Ip2_ViscBridge", "adamsperchard"); });
	expectContainsAll(m, { "Ip2_ViscBridge.normalModel", "'adamsperchard'", "'none'", "'adamsPerchard'", "'pitois'" });
	const std::string t = rejection([] { modelIndex<TangentialSlot>("Ip2_ViscBridge", "goldmann"); });
	expectContainsAll(t, { "tangentialModel", "goldmann", "'none', 'washino', 'slip', 'goldman'" });
	const std::string c = rejection([] { modelIndex<CapillarySlot>("Ip2_ViscBridge", "Willett"); });
	expectContainsAll(c, { "capillaryModel", "'Willett'", "'none', 'willett', 'rabinovich'" });
	EXPECT_FALSE(rejection([] { parseName("Law2", "integration", "", integrationNames); }).empty());
}

// What the checks that combine models rely on: only dissipative tangential models can be implicit,
// capillary forces are conservative and not dissipative, every enabled viscous model is dissipative
// except 'washino' (physics.md P7).
TEST(Registry, CapabilitiesAreConsistent)
{
	for (const auto& c : TangentialModels::capabilities)
		if (c.implicitCapable && c.enabled) EXPECT_TRUE(c.dissipative);
	EXPECT_FALSE(TangentialModels::capabilities[modelIndex<TangentialSlot>("x", "washino")].dissipative);
	for (std::size_t i = 1; i < CapillaryModels::size; ++i) {
		EXPECT_TRUE(CapillaryModels::capabilities[i].conservative);
		EXPECT_FALSE(CapillaryModels::capabilities[i].dissipative);
		EXPECT_TRUE(CapillaryModels::capabilities[i].beyondContact);
	}
	for (const auto& c : NormalModels::capabilities)
		EXPECT_TRUE(c.dissipative);
}

// Every combination of models has its own kernel index.
TEST(Registry, ComboIndicesAreDistinct)
{
	std::vector<bool> seen(comboCount, false);
	for (std::size_t n = 0; n < NormalModels::size; ++n)
		for (std::size_t t = 0; t < TangentialModels::size; ++t)
			for (std::size_t d = 0; d < DampingModels::size; ++d)
				for (std::size_t c = 0; c < CapillaryModels::size; ++c) {
					const std::size_t k = comboIndex({ n, t, d, c });
					ASSERT_LT(k, comboCount);
					EXPECT_FALSE(seen[k]);
					seen[k] = true;
				}
}

// The numeric parameters' table: every value outside its range is rejected, naming it.
TEST(Registry, ParameterSpecsRejectOutOfRange)
{
	for (const ParameterSpec& p : parameters::all) {
		EXPECT_NO_THROW(p.check("Ip2", p.defaultValue)) << p.name;
		const std::string below = rejection([&] { p.check("Ip2", p.lo - 1); });
		expectContainsAll(below, { "Ip2.", p.name });
		EXPECT_FALSE(rejection([&] { p.check("Ip2", std::nan("")); }).empty()) << p.name;
		if (std::isfinite(p.hi)) EXPECT_FALSE(rejection([&] { p.check("Ip2", p.hi * 1.5 + 1); }).empty()) << p.name;
		if (p.loOpen) EXPECT_FALSE(rejection([&] { p.check("Ip2", p.lo); }).empty()) << p.name;
	}
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
