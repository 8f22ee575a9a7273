// The error of a run estimated step by step, the time step a tolerance allows, and the cheaper of
// the two schemes for that step (physics.md §7a, A1–A5).  YADE-free: the time stepper sums the
// bodies' motion of each step into a StepMotion.
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>

namespace viscbridge {

// One step's motion and error, mass-weighted root mean squares over the dynamic bodies (A1).
struct StepMotion {
	double dt            = 0; // the step taken [s]
	double speed         = 0; // of the velocity it moved the bodies with [m/s]
	double velocityError = 0; // of each body's velocity error, A1; its position error is dt × this [m/s]
	double offset        = 0; // of each body's velocity offset, A1b: a position error of dt × this, not a velocity error [m/s]
	// A4b: the offsets o the next step's Δt can change, of the bodies nothing damps: Δt_{n+1} = Δt_n + δ
	// makes them o + ½δa; the means of m|o|², m o·a and m|a|² over the bodies' total mass
	double freeOffsetSq = 0, freeOffsetDotAcceleration = 0, freeAccelerationSq = 0;
	// A1c: of each body's carried velocity error [m/s], of the position error it made [m], and of the
	// share of the velocity error this step added [m/s]
	double carriedVelocity = 0, carriedPosition = 0, freshVelocity = 0;
	// A1e: of the velocity error the kinetic energy sees [m/s]: a body the implicit scheme holds with
	// the error of its velocity history, any other with its step's (velocityError's share)
	double historyVelocity = 0;
};

// A1c, for the controller: what a share of a step's velocity error, `raw` [m/s], that the step relaxed
// to `relaxed` = raw/(1 + z) amounts to over the steps it persists: the geometric series
// raw/(1 + z) · (1 + z)/z, with 1 + z read from how much the step relaxed it (at most 1000 steps'
// worth, for a share the bridges hardly relax).  For a stiff pair (z ≫ 1) it is the share itself;
// for one its steps resolve (z ≪ 1) the share of every later step it is carried through — what the
// run's error accumulates (A2), and the step's size sets.
inline double persistingShare(double raw, double relaxed)
{
	return raw > relaxed * (1 + 1e-3) ? relaxed * raw / (raw - relaxed) : 1e3 * relaxed;
}

// A2–A3: the two measures of bench/accuracy_cost.py — positions against the distance travelled, and
// the kinetic-energy history — accumulated over the run, and per step relative to the run's mean.
class AccuracyEstimate {
	double positionError = 0, path = 0;   // Σ Δt δv, Σ Δt |v|
	double energyError = 0, energy = 0;   // Σ Δt 2|v|δv, Σ Δt |v|²  (kinetic energy per unit mass, ×2)
	double time = 0, local = 0;
	double carried = 0; // A1c's position error now [m] (not saved: the next step has it)
	// not saved (the next step has them): the offset's part of local (A3), the velocity error's, the
	// speed the step is measured against, and the free offsets' quadratic in δ (A4b)
	double drift = 0, localVelocity = 0, controlledVelocity = 0, speedScale = 0, offsetSq = 0, offsetDotAcceleration = 0, accelerationSq = 0;
	// A4c: the velocity error the kinetic energy sees now, relative as the step's, and to the speed
	// now while that is at least nowShare of the run's mean (0 otherwise)
	double accumulated = 0, accumulatedNow = 0;
	double lastExcess = 0;
	double tightening = 1; // A4c: the share of the tolerance each step's own error is held to (saved)

public:
	void record(const StepMotion& m)
	{
		if (!(m.dt > 0) || !std::isfinite(m.speed) || !std::isfinite(m.velocityError) || !std::isfinite(m.offset)
		    || !std::isfinite(m.carriedVelocity) || !std::isfinite(m.carriedPosition) || !std::isfinite(m.historyVelocity))
			return;
		positionError += m.dt * std::hypot(m.velocityError, m.offset);
		carried = m.carriedPosition;
		path += m.dt * m.speed;
		energyError += m.dt * 2 * m.speed * std::hypot(m.historyVelocity, m.carriedVelocity);
		energy += m.dt * m.speed * m.speed;
		time += m.dt;
		// per step, relative to the run's mean so far, or to now if higher, so that a bed coming to
		// rest is not held to its own vanishing motion
		speedScale = std::max(path / time, m.speed);
		const double energyScale = std::max(energy / time, m.speed * m.speed);
		// the controller's measure: what this step made (A1c's carried error is made: a smaller step
		// does not undo it; its share of this step is)
		const auto relative = [&](double v) { return std::max(speedScale > 0 ? v / speedScale : 0, energyScale > 0 ? 2 * m.speed * v / energyScale : 0); };
		localVelocity      = relative(std::hypot(m.velocityError, m.freshVelocity));
		// A1c's share is derived, not calibrated: the controller holds it to `carriedShare` of the
		// tolerance, A1a's error to `calibration` of it (A4a)
		controlledVelocity = relative(std::hypot(m.velocityError, m.freshVelocity * std::sqrt(calibration / carriedShare)));
		const double seen  = std::hypot(m.historyVelocity, m.carriedVelocity);
		accumulated        = relative(seen);
		accumulatedNow     = m.speed > nowShare * path / time ? 2 * seen / m.speed : 0;
		drift         = speedScale > 0 ? m.offset / speedScale : 0;
		local         = std::max(localVelocity, drift);
		offsetSq = m.freeOffsetSq, offsetDotAcceleration = m.freeOffsetDotAcceleration, accelerationSq = m.freeAccelerationSq;
	}
	double stepError() const { return local; }
	bool   started() const { return time > 0; }
	double runError() const
	{
		return std::max(path > 0 ? (positionError + carried) / path : 0, energy > 0 ? energyError / energy : 0);
	}
	void reset() { *this = AccuracyEstimate(); }
	// The state a saved scene resumes from.
	static constexpr int stateSize = 6;
	void save(double out[stateSize]) const
	{
		out[0] = positionError, out[1] = path, out[2] = energyError, out[3] = energy, out[4] = time, out[5] = local;
	}
	void restore(const double in[stateSize])
	{
		positionError = in[0], path = in[1], energyError = in[2], energy = in[3], time = in[4], local = localVelocity = controlledVelocity = in[5];
	}

	// A4: the step at which the last one's error would meet `tolerance`.  The error per unit step
	// grows like Δt² on contact springs and like Δt on bridges' drift: the square root (the cautious
	// one of the two when growing), with a margin; shrinking at most 5× at once (one rough step does
	// not collapse the run); infinite while nothing changes.
	// `stableStep`: the stability limit's step [s] (A4b's least speed; 0: none known).
	double allowedStep(double lastDt, double tolerance, double stableStep = 0) const
	{
		const double forOffset = offsetStep(lastDt, tolerance, stableStep);
		if (!(controlledVelocity > 0)) return forOffset;
		return std::min(forOffset, lastDt * std::max(0.2, controllerMargin * std::sqrt(calibration * localTolerance(tolerance) / controlledVelocity)));
	}
	// A4c: what the steps' errors have accumulated to (A1c's carried error, A1e's history) is made: a
	// smaller step does not undo it, but it makes the steps that follow add less.  While it exceeds
	// its share of the tolerance and still grows, the share of the tolerance each step's own error is
	// held to falls by (share/excess)^0.1 per step (an integral control: the accumulated error answers
	// a change of Δt only over the steps it persists); otherwise it grows back by 3.5 % per step, to 1
	// (an error the bridges relax, or one no step can undo, does not hold the run at small steps).
	// Never below minTightening: an error that grows at any Δt (a mode nothing damps) costs at most
	// 10x the steps.  The excess is measured as A3 measures a step, against the run's mean motion or
	// the motion now if faster (a bed coming to rest is not held to its own vanishing motion); and,
	// once the run's e_K exceeds the share, against the motion now while that is at least a third of
	// the run's mean speed (what e_K adds then is 2|δv|/|v| of the step's weight: the 45-sphere bed at
	// 1 Pa·s, slowing to a third of its mean speed, ended 1.8x over 1e-2 without it; below a third,
	// the stiffening pair's rest after it stopped cost 5x the steps at 1e-4 for the same error).
	double localTolerance(double tolerance) const { return tolerance * tightening; }
	double tighteningNow() const { return tightening; }
	void tighten(double tolerance)
	{
		const double share   = historyShare * tolerance;
		const double excess  = energy > 0 && energyError / energy > share ? std::max(accumulated, accumulatedNow) : accumulated;
		const bool   growing = excess > lastExcess;
		lastExcess           = excess;
		if (!std::isfinite(excess) || !(tolerance > 0)) return;
		const double factor = excess > share && growing ? std::pow(share / excess, tighteningRate) : relaxingRate;
		tightening          = std::clamp(tightening * factor, minTightening, 1.0);
	}
	static constexpr double tighteningRate = 0.1, relaxingRate = 1.035, minTightening = 1e-2;
	// A4c's state, saved after the sums (older scenes: none, the defaults)
	static constexpr int controllerStateSize = 2;
	void saveController(double out[controllerStateSize]) const { out[0] = tightening, out[1] = lastExcess; }
	void restoreController(const double in[controllerStateSize])
	{
		tightening = std::isfinite(in[0]) ? std::clamp(in[0], minTightening, 1.0) : 1.0;
		lastExcess = std::isfinite(in[1]) ? in[1] : 0;
	}
	// A4b: the largest Δt_{n+1} = Δt_n + δ that keeps the free offsets, o + ½δa, within half the
	// tolerance of the speed (their estimate is exact: no calibration; the other half is the rest's).
	// None if no δ can (what is offset is offset: the error is made, a smaller step does not undo it).
	// The speed is at least what the free accelerations give in one step at the stability limit
	// `stableStep`: from rest U → 0, and ½aΔt held to a vanishing U would shrink Δt without end (a
	// drum's falling cloud went to 1e-11 s, where its positions no longer moved in double precision).
	double offsetStep(double lastDt, double tolerance, double stableStep = 0) const
	{
		const double inf = std::numeric_limits<double>::infinity();
		const double least  = std::isfinite(stableStep) && stableStep > 0 ? std::sqrt(accelerationSq) * stableStep : 0;
		const double target = controllerMargin * 0.5 * tolerance * std::max(speedScale, least);
		const double A = 0.25 * accelerationSq, B = offsetDotAcceleration, C = offsetSq - target * target;
		const double disc = B * B - 4 * A * C;
		if (!(A > 0) || !(disc >= 0)) return inf;
		return lastDt + std::max(-0.8 * lastDt, (std::sqrt(disc) - B) / (2 * A));
	}
	static constexpr double controllerMargin = 0.9;
	// A4a: the estimate aims at this fraction of the tolerance: calibrated on bench/accuracy_target.py,
	// where the run's true error was 0.05–10× its estimate — under at low viscosity, over at high
	// (docs/performance.md §1)
	static constexpr double calibration = 0.1;
	// A1c: the share of the tolerance the carried error's growth is held to (what the run's error
	// adds up, A2, without A1a's calibration: its estimate is the error itself, not a local proxy)
	static constexpr double carriedShare = 0.5;
	// A4c: the share of the tolerance the accumulated error may take before the steps are tightened
	static constexpr double historyShare = 0.5;
	// A4c: the speed, as a share of the run's mean, from which the excess is measured against it
	static constexpr double nowShare = 1.0 / 3;
	// A4: before any step is known, the run starts at 1 % of `tolerance` × the stability limit (an
	// error committed cannot be undone: no step is taken twice; at `tolerance` × the limit, the first
	// step of a 45-sphere bed at 1 Pa·s erred by 4.5 % of its speed at tolerance 1e-2), and the controller
	// lets it grow by up to `growth` per step while the estimate allows.
	static double firstStep(double limit, double tolerance) { return firstStepShare * tolerance * limit; }
	static constexpr double firstStepShare = 1e-2;
	static constexpr double growth = 2;
};

// A5: the scheme whose cost over a stretch of time is lower: explicit steps cost 1 each and are
// limited by `explicitLimit`, implicit ones cost `implicitCost` and are limited by `implicitLimit`;
// both by the accuracy step.  The running scheme keeps its place unless the other is cheaper by
// the factor `hysteresis` (a scene near the break-even point does not switch every step).
inline bool implicitIsCheaper(bool runningImplicit, double accuracyStep, double explicitLimit, double implicitLimit, double implicitCost,
                              double hysteresis = 1.5)
{
	const double explicitRate = 1 / std::min(accuracyStep, explicitLimit);                 // steps per second
	const double implicitRate = implicitCost / std::min(accuracyStep, implicitLimit); // explicit steps' worth per second
	return runningImplicit ? implicitRate < hysteresis * explicitRate : hysteresis * implicitRate < explicitRate;
}

} // namespace viscbridge
