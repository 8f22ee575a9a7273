// The liquid rules L1–L3 of physics.md §11, by hand.
#include "viscbridge/core/liquid/FilmExchange.hpp"
#include <gtest/gtest.h>

using namespace viscbridge;

TEST(FilmExchange, OfferSplitsAFilmOverTheStepsNewBridges)
{
	EXPECT_DOUBLE_EQ(filmOffer(3e-12, 3), 1e-12);
	EXPECT_DOUBLE_EQ(filmOffer(3e-12, 0), 0.0);
}

TEST(FilmExchange, BelowTheCapABridgeTakesBothOffers)
{
	const FilmTake t = takeFromFilms(1e-12, 2e-12, 1e-11);
	EXPECT_DOUBLE_EQ(t.volume, 3e-12);
	EXPECT_DOUBLE_EQ(t.from1, 1e-12);
	EXPECT_DOUBLE_EQ(t.from2, 2e-12);
}

TEST(FilmExchange, AtTheCapEachSideGivesInProportionAndKeepsTheRest)
{
	const FilmTake t = takeFromFilms(3e-12, 1e-12, 2e-12);
	EXPECT_DOUBLE_EQ(t.volume, 2e-12);
	EXPECT_DOUBLE_EQ(t.from1, 1.5e-12);
	EXPECT_DOUBLE_EQ(t.from2, 0.5e-12);
	EXPECT_DOUBLE_EQ(t.from1 + t.from2, t.volume);
}

TEST(FilmExchange, NoLiquidNoBridge)
{
	const FilmTake t = takeFromFilms(0, 0, 1e-11);
	EXPECT_EQ(t.volume, 0.0);
}

TEST(FilmExchange, RuptureSharesHalfOrBySurfaceAndAllToTheParticleOfAWall)
{
	EXPECT_DOUBLE_EQ(ruptureShare1(RuptureSplit::half, 1e-3, 2e-3), 0.5);
	EXPECT_DOUBLE_EQ(ruptureShare1(RuptureSplit::radius, 1e-3, 2e-3), 0.2);
	EXPECT_DOUBLE_EQ(ruptureShare1(RuptureSplit::half, 0, 1e-3), 0.0);    // side 1 a wall
	EXPECT_DOUBLE_EQ(ruptureShare1(RuptureSplit::radius, 1e-3, 0), 1.0);  // side 2 a wall
}
