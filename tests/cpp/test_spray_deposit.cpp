// Where sprayed binder lands, L6 and L7 of physics.md §11: the area each sphere shows the nozzle,
// and the capped share.
#include "test_support.hpp"
#include "viscbridge/core/liquid/SprayDeposit.hpp"
#include <gtest/gtest.h>
#include <numeric>
#include <random>

using namespace viscbridge;
using vbtest::kPi;

namespace {
const Vec3 kDown(0, 0, -1);
// The pixel grid resolves a disc of r = 5 pixels: its area to a few per cent.
constexpr double kDiscTolerance = 0.04;
} // namespace

// A column of touching spheres under a nozzle above: the top one shows its whole disc, the others
// are hidden.  Seen from the side, every one shows its disc.
TEST(SprayShadow, ATopSphereHidesTheColumnBelowIt)
{
	const double              r = 1e-3;
	const std::vector<Vec3>   centres { Vec3(0, 0, 0), Vec3(0, 0, 2 * r), Vec3(0, 0, 4 * r) };
	const std::vector<double> radii(3, r);
	SprayShadow               shadow;
	std::vector<double>       area;
	shadow.exposedAreas(centres, radii, kDown, area);
	EXPECT_EQ(area[0], 0.0);
	EXPECT_EQ(area[1], 0.0);
	EXPECT_NEAR(area[2], kPi * r * r, kDiscTolerance * kPi * r * r);
	shadow.exposedAreas(centres, radii, Vec3(1, 0, 0), area);
	for (const double a : area) EXPECT_NEAR(a, kPi * r * r, kDiscTolerance * kPi * r * r);
}

// A small sphere resting on a larger one's top is what the nozzle sees there: the large one keeps
// its disc minus the small one's; both add up to the large disc (the column's shadow).
TEST(SprayShadow, ASphereOnTopTakesItsDiscFromTheOneBelow)
{
	const double              R = 2e-3, r = 0.5e-3;
	const std::vector<Vec3>   centres { Vec3(0, 0, 0), Vec3(0, 0, R + r) };
	const std::vector<double> radii { R, r };
	SprayShadow               shadow;
	std::vector<double>       area;
	shadow.exposedAreas(centres, radii, kDown, area);
	EXPECT_NEAR(area[1], kPi * r * r, kDiscTolerance * kPi * r * r);
	EXPECT_NEAR(area[0] + area[1], kPi * R * R, 0.02 * kPi * R * R);
	EXPECT_NEAR(area[0], kPi * (R * R - r * r), 0.02 * kPi * R * R);
}

// A random bed: the exposed areas never exceed a sphere's disc, sum to about the area of the
// shadow (at most the sum of the discs), and the spheres seen are the ones nearest the nozzle in
// their column (the highest sphere of the bed is always seen).
TEST(SprayShadow, ARandomBedShowsItsTopLayer)
{
	std::mt19937        g(7);
	std::vector<Vec3>   centres;
	std::vector<double> radii;
	for (int i = 0; i < 800; ++i) {
		centres.push_back(Vec3(vbtest::uniform(g, 0, 0.02), vbtest::uniform(g, 0, 0.02), vbtest::uniform(g, 0, 0.02)));
		radii.push_back(vbtest::uniform(g, 0.8e-3, 1e-3));
	}
	SprayShadow         shadow;
	std::vector<double> area;
	shadow.exposedAreas(centres, radii, kDown, area);
	double discs = 0, seen = 0;
	for (std::size_t i = 0; i < area.size(); ++i) {
		EXPECT_LE(area[i], 1.08 * kPi * radii[i] * radii[i]); // a disc anywhere on the grid: ±8 % (~6 boundary pixels)
		discs += kPi * radii[i] * radii[i];
		seen += area[i];
	}
	EXPECT_LT(seen, 0.35 * discs);       // a bed five discs deep hides most of itself
	EXPECT_GT(seen, 0.9 * 0.02 * 0.02); // and covers its 2 cm × 2 cm footprint
	const auto top = std::max_element(centres.begin(), centres.end(), [](const Vec3& a, const Vec3& b) { return a.z() < b.z(); });
	EXPECT_GT(area[static_cast<std::size_t>(top - centres.begin())], 0.5 * kPi * 0.64e-6);
}

// L7 without a cap in reach: proportional to the weights; nothing left.
TEST(SprayShare, ProportionalToTheWeightsWhenNothingIsFull)
{
	std::vector<double> given;
	const double        left = shareWithinRoom({ 1, 3 }, { 1, 1 }, 0.4, given);
	EXPECT_DOUBLE_EQ(given[0], 0.1);
	EXPECT_DOUBLE_EQ(given[1], 0.3);
	EXPECT_EQ(left, 0.0);
}

// L7: a receiver that reaches its cap keeps at it, the rest goes to the others in proportion.
TEST(SprayShare, WhatAFullReceiverCannotTakeGoesToTheOthers)
{
	std::vector<double> given;
	const double        left = shareWithinRoom({ 1, 1, 2 }, { 0.05, 1, 1 }, 1.0, given);
	EXPECT_DOUBLE_EQ(given[0], 0.05);
	EXPECT_NEAR(given[1], 0.95 / 3, 1e-15);
	EXPECT_NEAR(given[2], 2 * 0.95 / 3, 1e-15);
	EXPECT_EQ(left, 0.0);
}

// L7: when every receiver is full, what is left waits (is returned); nothing is lost.
TEST(SprayShare, WhenAllAreFullTheRestIsReturned)
{
	std::vector<double> given;
	const double        left = shareWithinRoom({ 1, 2 }, { 0.1, 0.2 }, 1.0, given);
	EXPECT_DOUBLE_EQ(given[0], 0.1);
	EXPECT_DOUBLE_EQ(given[1], 0.2);
	EXPECT_NEAR(left, 0.7, 1e-15);
	EXPECT_EQ(shareWithinRoom({}, {}, 1.0, given), 1.0); // no receiver at all
}

// Conservation and the cap over random receivers: given + left = amount to round-off, no
// receiver above its room, and a receiver below its room got its weight's share at the final rate.
TEST(SprayShare, ConservesAndRespectsEveryRoom)
{
	std::mt19937 g(3);
	for (int trial = 0; trial < 200; ++trial) {
		const std::size_t   n = 1 + trial % 17;
		std::vector<double> w(n), room(n), given;
		for (std::size_t i = 0; i < n; ++i) w[i] = vbtest::uniform(g, 0, 1), room[i] = vbtest::logUniform(g, 1e-3, 1);
		const double amount = vbtest::logUniform(g, 1e-3, 2 * n);
		const double left   = shareWithinRoom(w, room, amount, given);
		EXPECT_NEAR(std::accumulate(given.begin(), given.end(), 0.0) + left, amount, 1e-12 * amount);
		double rate = -1;
		for (std::size_t i = 0; i < n; ++i) {
			EXPECT_LE(given[i], room[i] * (1 + 1e-15));
			if (given[i] < room[i] * (1 - 1e-12)) {
				EXPECT_EQ(left, 0.0); // someone still had room: nothing waits
				if (rate < 0) rate = given[i] / w[i];
				EXPECT_NEAR(given[i] / w[i], rate, 1e-9 * rate);
			}
		}
	}
}

// L6b: whole droplets, each on one receiver; the remainder below a droplet waits; the draws depend
// on (seed, counter) only, so a spray resumed with its counter lands the next droplets as the
// uninterrupted one does.
TEST(SprayDroplets, WholeDropletsLandByWeightAndTheRestWaits)
{
	std::vector<double> given;
	std::uint64_t       counter = 0;
	const double        left    = shareAsDroplets({ 1, 3 }, { 1, 1 }, 10.5e-3, 1e-3, 7, counter, given);
	EXPECT_NEAR(left, 0.5e-3, 1e-15);
	EXPECT_EQ(counter, 10u);
	for (const double g : given) EXPECT_NEAR(std::fmod(g + 1e-12, 1e-3), 0.0, 1e-9); // whole droplets
	EXPECT_NEAR(given[0] + given[1], 10e-3, 1e-15);
	// many droplets: the shares follow the weights (1 : 3) to sampling error
	counter = 0;
	shareAsDroplets({ 1, 3 }, { 1e9, 1e9 }, 4000.0, 1.0, 7, counter, given);
	EXPECT_NEAR(given[1] / 4000.0, 0.75, 0.03);
	// resumed: the draws of droplets 2000–3999 alone are those of the second half of one run
	std::uint64_t       c1 = 0, c2 = 2000;
	std::vector<double> whole, half;
	shareAsDroplets({ 1, 3 }, { 1e9, 1e9 }, 2000.0, 1.0, 7, c1, half);
	shareAsDroplets({ 1, 3 }, { 1e9, 1e9 }, 2000.0, 1.0, 7, c2, whole);
	EXPECT_EQ(half[0] + whole[0], given[0]);
}

// L7 with droplets: a droplet goes only where it fits; when no receiver has room, it waits.
TEST(SprayDroplets, ADropletGoesOnlyWhereItFits)
{
	std::vector<double> given;
	std::uint64_t       counter = 0;
	const double        left    = shareAsDroplets({ 5, 1 }, { 2.5, 1.0 }, 10.0, 1.0, 3, counter, given);
	EXPECT_EQ(given[0], 2.0); // room 2.5: two droplets, the third would not fit
	EXPECT_EQ(given[1], 1.0);
	EXPECT_EQ(left, 7.0);
	EXPECT_EQ(shareAsDroplets({}, {}, 3.0, 1.0, 3, counter, given), 3.0);
}
