// The accuracy kernel (physics.md §7a): the run's error from its steps (A2, A3), the step a
// tolerance allows (A4) and the cheaper scheme (A5).
#include "viscbridge/core/timestep/AccuracyControl.hpp"
#include <gtest/gtest.h>
#include <cmath>
#include <limits>

using viscbridge::AccuracyEstimate;
using viscbridge::implicitIsCheaper;
using viscbridge::persistingShare;
using viscbridge::StepMotion;

TEST(AccuracyControl, RunErrorIsTheRelativeErrorOfItsSteps)
{
	// every step off by 1 % of its velocity: positions off by 1 % of the distance travelled, and the
	// kinetic energy by 2 %
	AccuracyEstimate e;
	for (int n = 0; n < 100; ++n) {
		StepMotion m { 1e-6 * (1 + n % 3), 0.1 + 0.001 * n, 0.001 + 1e-5 * n };
		m.historyVelocity = m.velocityError; // the kinetic energy sees the same error (no implicit history, A1e)
		e.record(m);
	}
	EXPECT_NEAR(e.runError(), 0.02, 1e-12);
	EXPECT_NEAR(e.stepError(), 0.02, 1e-12);
}

TEST(AccuracyControl, TheKineticMeasureTakesTheVelocityHistorysError)
{
	// A1e: each step 1 % off locally while the velocity history is 5 % off: positions are off by
	// the step errors' sum (1 %), the kinetic energy by twice the history's (10 %), not by twice 1 %
	AccuracyEstimate e;
	for (int n = 0; n < 50; ++n) {
		StepMotion m { 1e-6, 0.1, 0.001 };
		m.historyVelocity = 0.005;
		e.record(m);
	}
	EXPECT_NEAR(e.runError(), 0.1, 1e-12);
	EXPECT_NEAR(e.stepError(), 0.02, 1e-12); // the controller's measure is the step's own
}

TEST(AccuracyControl, ABedComingToRestIsMeasuredAgainstTheMotionItHad)
{
	// the speed falls a thousandfold while each step's error stays a tenth of the speed: the step
	// error, relative to the run's mean speed, falls with it, and the controller lets dt grow
	AccuracyEstimate e;
	double speed = 0.1;
	for (int n = 0; n < 200; ++n, speed *= 0.966) e.record(StepMotion { 1e-6, speed, 0.1 * speed });
	EXPECT_LT(speed, 1.2e-4);
	EXPECT_LT(e.stepError(), 1e-2);
	EXPECT_GT(e.allowedStep(1e-6, 1e-1), 1e-6);
}

TEST(AccuracyControl, TheAllowedStepMeetsTheCalibratedTolerance)
{
	AccuracyEstimate e;
	const double tol = 1e-2, target = AccuracyEstimate::calibration * tol;
	e.record(StepMotion { 1e-6, 1.0, 0.25 * target }); // half the target (the energy measure doubles it): √2 × 0.9
	EXPECT_NEAR(e.allowedStep(1e-6, tol), 1e-6 * AccuracyEstimate::controllerMargin * std::sqrt(2.0), 1e-15);
	AccuracyEstimate rough;
	rough.record(StepMotion { 1e-6, 1.0, 1.0 }); // a step 100× off: shrink, but by at most 5× at once
	EXPECT_DOUBLE_EQ(rough.allowedStep(1e-6, tol), 0.2e-6);
	AccuracyEstimate still; // nothing changed: no accuracy limit
	still.record(StepMotion { 1e-6, 0.0, 0.0 });
	EXPECT_TRUE(std::isinf(still.allowedStep(1e-6, tol)));
	EXPECT_FALSE(AccuracyEstimate().started());
}

TEST(AccuracyControl, AFreeFallsOffsetSetsTheStepThatKeepsItWithinHalfTheTolerance)
{
	// A1b, A4b: a sphere falling at 0.1 m/s with Δt = 1e-5 s carries the offset ½Δt·g; at 1e-3 the
	// offset may be 0.9 × ½ × 1e-3 of the speed, which ½Δt·g is at Δt = 2 × 4.5e-5 m/s / g
	const double g = 9.81, dt = 1e-5, o = 0.5 * dt * g;
	AccuracyEstimate e;
	e.record(StepMotion { dt, 0.1, 0.0, o, o * o, o * g, g * g });
	EXPECT_NEAR(e.stepError(), o / 0.1, 1e-15);
	EXPECT_NEAR(e.allowedStep(dt, 1e-3), 2 * 0.9 * 0.5e-3 * 0.1 / g, 1e-15);
	EXPECT_NEAR(e.runError(), o / 0.1, 1e-15); // positions only: the kinetic energy is not offset
	// an offset no step can take back (across the acceleration, the error is made): no limit from it
	AccuracyEstimate across;
	across.record(StepMotion { dt, 0.1, 0.0, 1e-3, 1e-6, 0.0, g * g });
	EXPECT_TRUE(std::isinf(across.allowedStep(dt, 1e-3)));
	// a body nothing accelerates: its offset stays whatever Δt is
	AccuracyEstimate coasting;
	coasting.record(StepMotion { dt, 0.1, 0.0, 1e-3, 1e-6, 0.0, 0.0 });
	EXPECT_TRUE(std::isinf(coasting.allowedStep(dt, 1e-3)));
}

TEST(AccuracyControl, AFallFromRestIsMeasuredAgainstTheSpeedOfOneStableStep)
{
	// A4b: a cloud released from rest falls at g·t after its first step Δt₁; its offset ½gΔt₁ held
	// to the tolerance of that vanishing speed would shrink Δt step after step (a drum's cloud went
	// to 1e-11 s, where its positions no longer moved).  Against the speed g·h one step at the
	// stability limit h gives, the step may grow to 0.9·tol·h (twice 0.9 × ½ tol × g·h / g)
	const double g = 9.81, h = 1.5e-5, dt = 1e-4 * h, o = 0.5 * dt * g, tol = 1e-2;
	AccuracyEstimate e;
	e.record(StepMotion { dt, g * dt, 0.0, o, o * o, o * g, g * g });
	EXPECT_NEAR(e.allowedStep(dt, tol), 0.2 * dt, 1e-20); // measured against g·Δt₁ alone: cut 5×
	EXPECT_NEAR(e.allowedStep(dt, tol, h), 2 * 0.9 * 0.5 * tol * h, 1e-18);
	EXPECT_GT(e.allowedStep(dt, tol, h), 10 * dt);
	// a body already faster than g·h keeps its own speed as the measure
	AccuracyEstimate fast;
	fast.record(StepMotion { dt, 0.1, 0.0, o, o * o, o * g, g * g });
	EXPECT_DOUBLE_EQ(fast.allowedStep(dt, tol, h), fast.allowedStep(dt, tol));
}

TEST(AccuracyControl, ACarriedErrorCountsInTheRunButOnlyItsNewShareInTheStep)
{
	// A1c: a pair that stopped 1e-8 m off after travelling 1e-5 m has a run error of 1e-3 however
	// small its steps now are; the controller sees only what the step added, so a carried error
	// does not shrink the step (a smaller step would not undo it), while a share of it made in this
	// step does, as a step's own error would
	StepMotion still { 1e-6, 1.0, 0, 0 };
	still.carriedPosition = 1e-8;
	AccuracyEstimate carried;
	for (int n = 0; n < 10; ++n) carried.record(still); // 10 steps at 1 m/s: 1e-5 m
	EXPECT_NEAR(carried.runError(), 1e-3, 1e-15);
	still.carriedVelocity = 0.5; // half the speed carried: the energy history is off, the step is not
	AccuracyEstimate slow;
	slow.record(still);
	EXPECT_NEAR(slow.runError(), 1.0, 1e-12); // 2|v||ε|/|v|² of the kinetic energy
	EXPECT_EQ(slow.stepError(), 0);
	EXPECT_EQ(slow.allowedStep(1e-6, 1e-2), std::numeric_limits<double>::infinity());
	still.freshVelocity = 0.5;
	AccuracyEstimate made;
	made.record(still);
	EXPECT_NEAR(made.stepError(), 1.0, 1e-12);
	EXPECT_NEAR(made.allowedStep(1e-6, 1e-2), 0.2e-6, 1e-18); // shrinks, by at most 5× at once
}

TEST(AccuracyControl, AStepsShareCountsOverTheStepsItPersists)
{
	// a share relaxed to 1/(1 + z) per step adds 1/(1+z) + 1/(1+z)² + … = 1/z of itself to the
	// velocity errors of the steps that follow: once for a stiff bridge, 100× for a soft one
	for (const double z : { 100.0, 1.0, 0.01 })
		EXPECT_NEAR(persistingShare(2.0, 2.0 / (1 + z)), 2.0 / z, 1e-9 / z) << z;
	// one the step does not relax at all (a free body's) counts as 1000 steps' worth, not infinitely
	EXPECT_DOUBLE_EQ(persistingShare(2.0, 2.0), 2000.0);
	EXPECT_EQ(persistingShare(0.0, 0.0), 0.0);
}

TEST(AccuracyControl, AnAccumulatedErrorThatGrowsTightensTheStepsAndOneThatDecaysLetsThemGrowBack)
{
	// A4c: each step 0.1 % off locally (within its calibrated share at tol = 1e-2) while the
	// accumulated velocity error grows past half the tolerance: the share each step is held to falls,
	// never below minTightening, and the allowed step with it; once the accumulated error decays the
	// share grows back to 1
	const double tol = 1e-2;
	AccuracyEstimate e;
	StepMotion       m { 1e-6, 1.0, 1e-4 };
	const double     plain = [&] { AccuracyEstimate fresh; fresh.record(m); fresh.tighten(tol); return fresh.allowedStep(1e-6, tol); }();
	for (int n = 0; n < 400; ++n) {
		m.historyVelocity = 1e-2 * (1 + 0.01 * n); // 2|δv|/|v| from 2 % up: over ½ tol, and growing
		e.record(m);
		e.tighten(tol);
	}
	EXPECT_NEAR(e.tighteningNow(), AccuracyEstimate::minTightening, 1e-15);
	EXPECT_NEAR(e.allowedStep(1e-6, tol) / plain, std::sqrt(AccuracyEstimate::minTightening), 1e-9);
	for (int n = 0; n < 400; ++n) {
		m.historyVelocity *= 0.99; // decaying: whether over the share or not, the steps may grow back
		e.record(m);
		e.tighten(tol);
	}
	EXPECT_EQ(e.tighteningNow(), 1.0);
}

TEST(AccuracyControl, TheViscousLimitMakesTheImplicitSchemeCheaper)
{
	const double inf = std::numeric_limits<double>::infinity();
	// 100 Pa·s: the explicit limit 10⁴× below the collision limit
	EXPECT_TRUE(implicitIsCheaper(false, inf, 1e-9, 1e-5, 3));
	// dry: both limits are the collision limit, an implicit step costs 3 explicit ones
	EXPECT_FALSE(implicitIsCheaper(false, inf, 1e-5, 1e-5, 3));
	// the tolerance allows less than the explicit limit: explicit
	EXPECT_FALSE(implicitIsCheaper(false, 1e-9, 2e-9, 1e-5, 3));
	// near the break-even point the running scheme stays (hysteresis 1.5)
	EXPECT_TRUE(implicitIsCheaper(true, inf, 1e-5 / 2.5, 1e-5, 3));
	EXPECT_FALSE(implicitIsCheaper(false, inf, 1e-5 / 4, 1e-5, 3));
	EXPECT_TRUE(implicitIsCheaper(false, inf, 1e-5 / 5, 1e-5, 3));
}
