#include "viscbridge/engines/ViscBridgeSpray.hpp"
#include "viscbridge/core/util/Validation.hpp"
#include "viscbridge/distributed/Distributed.hpp"
#include "viscbridge/yade/ViscBridgeContext.hpp"
#include "viscbridge/yade/ViscBridgeState.hpp"
#include <core/Scene.hpp>
#include <pkg/common/Sphere.hpp>
#include <sstream>

namespace yade {

CREATE_LOGGER(ViscBridgeSpray);

namespace vb = viscbridge;

namespace {
	const std::string kOwner = "ViscBridgeSpray";
	std::string       fmt(Real v) { return vb::formatValue(v); }
	std::string       vec(const Vector3r& v) { return "(" + fmt(v[0]) + ", " + fmt(v[1]) + ", " + fmt(v[2]) + ")"; }
}

void ViscBridgeSpray::postLoad(ViscBridgeSpray&)
{
	rollback.check(checked(), [&] {
		vb::requireNonNegative(kOwner, "rate", rate, " [m³/s]");
		vb::requireNonNegative(kOwner, "start", start, " [s]");
		if (end >= 0 && !(end > start)) vb::rejectValue(kOwner, "end", end, "> start=" + fmt(start) + " [s], or < 0 for a spray that never stops");
		vb::requireFinite(kOwner, "end", end, "a finite time [s], < 0 for a spray that never stops");
		vb::requirePositive(kOwner, "maxFilmRel", maxFilmRel);
		vb::requireNonNegative(kOwner, "ballRadius", ballRadius, " [m]; 0: the zone is the box");
		vb::requireNonNegative(kOwner, "dropletVolume", dropletVolume, " [m³]; 0: a fine mist");
		for (int k = 0; k < 3; ++k) vb::requireFinite(kOwner, "nozzle", nozzle[k], "a finite direction (zero: no shadow)");
	});
}

void ViscBridgeSpray::checkZone() const
{
	// the corners are set one after the other: checked when the spray runs, not at each assignment
	for (int k = 0; k < 3; ++k)
		if (ballRadius == 0 && !(boxMin[k] <= boxMax[k]))
			throw std::invalid_argument(kOwner + ": the box zone boxMin=" + vec(boxMin) + ", boxMax=" + vec(boxMax)
			                            + " is empty; allowed: boxMin <= boxMax in every axis [m] (or ballRadius > 0 for a ball).");
}

bool ViscBridgeSpray::inZone(const Vector3r& x) const
{
	if (ballRadius > 0) return (x - ballCentre).squaredNorm() <= ballRadius * ballRadius;
	return (x.array() >= boxMin.array()).all() && (x.array() <= boxMax.array()).all();
}

void ViscBridgeSpray::action()
{
	if (distributed::active(scene))
		throw std::runtime_error(kOwner + " does not run under yade.mpy (the films it wets live on other ranks); spray in a serial "
		                                  "run or with threads (-j).");
	checkZone();
	// films feed bridges only with conserved liquid: with 'fixed' liquid a spray would add to a total nothing uses
	if (!ViscBridgeContext::hasEngine(scene, "ViscBridgeLiquid"))
		throw std::runtime_error(kOwner + " sprays onto the particles' films, which only Ip2_FrictMat_FrictMat_ViscBridgePhys.liquidModel='film' "
		                                  "uses (with a ViscBridgeLiquid engine in O.engines: viscbridge.engines(liquidModel='film') inserts it); "
		                                  "this scene has none.");
	// it runs after the integrator: the positions are those of the end of the step, time + dt
	const Real now = scene->time + scene->dt;
	accountSprayed(now);
	if (pending > 0) deliver(end >= 0 && now >= end);
	if (end >= 0 && now >= end && pending > std::max(1e-3 * sprayed, dropletVolume))
		warnOnce(warnedAfterEnd, "the spray window ended at t = " + fmt(end) + " s with " + fmt(pending) + " m³ (" + fmt(100 * pending / sprayed)
		                                 + " % of what it sprayed) not yet in a film: it goes to the spheres the spray reaches later, at most maxFilmRel = "
		                                 + fmt(maxFilmRel) + " of each one's volume");
}

void ViscBridgeSpray::accountSprayed(Real now)
{
	const Real from  = std::max(accountedUntil, start);
	const Real until = end >= 0 ? std::min(now, end) : now;
	if (until > from) {
		pending += rate * (until - from);
		sprayed += rate * (until - from);
	}
	accountedUntil = std::max(accountedUntil, now);
}

void ViscBridgeSpray::collectTargets()
{
	ids.clear(), centres.clear(), radii.clear();
	for (const auto& b : *scene->bodies) {
		const auto* sphere = b ? dynamic_cast<const Sphere*>(b->shape.get()) : nullptr;
		if (!sphere || !inZone(b->state->pos)) continue;
		ids.push_back(b->getId());
		centres.push_back(b->state->pos);
		radii.push_back(sphere->radius);
	}
}

void ViscBridgeSpray::weigh()
{
	// L6: the area each shows the nozzle (the cross-section, without a nozzle direction); L7: room up to the cap
	if (nozzle.squaredNorm() > 0) shadow.exposedAreas(centres, radii, nozzle.normalized(), weight);
	else {
		weight.resize(radii.size());
		for (std::size_t i = 0; i < radii.size(); ++i) weight[i] = vb::pi * radii[i] * radii[i];
	}
	room.resize(ids.size());
	for (std::size_t i = 0; i < ids.size(); ++i) {
		const ViscBridgeState* s = ViscBridgeState::peek(*Body::byId(ids[i], scene));
		if (s && !s->wettable) weight[i] = 0; // hides, takes nothing
		const Real film = s ? s->film : 0;
		room[i]         = std::max<Real>(0, maxFilmRel * 4.0 / 3.0 * vb::pi * std::pow(radii[i], 3) - film);
	}
}

void ViscBridgeSpray::deliver(bool windowOver)
{
	collectTargets();
	weigh();
	const Real offered = pending;
	if (dropletVolume > 0) {
		// once the window is over, what is left of the last droplet lands as a smaller one
		const Real    droplet = windowOver ? std::min(dropletVolume, offered) : dropletVolume;
		std::uint64_t counter = static_cast<std::uint64_t>(droplets);
		pending               = vb::shareAsDroplets(weight, room, offered, droplet, static_cast<std::uint64_t>(seed), counter, given);
		droplets              = static_cast<long>(counter);
	} else {
		pending = vb::shareWithinRoom(weight, room, offered, given);
	}
	receivers          = 0;
	for (std::size_t i = 0; i < ids.size(); ++i) {
		if (!(given[i] > 0)) continue;
		ViscBridgeState::of(*Body::byId(ids[i], scene)).film += given[i];
		++receivers;
	}
	delivered += offered - pending;
	if (!(pending > 0) || (dropletVolume > 0 && pending < dropletVolume)) return; // less than a droplet waits for the next
	if (std::any_of(weight.begin(), weight.end(), [](double w) { return w > 0; }))
		warnOnce(warnedFull, "every sphere it reaches holds maxFilmRel = " + fmt(maxFilmRel) + " of its volume: " + fmt(pending)
		                             + " m³ waits until a sphere with room comes into reach");
	else
		warnOnce(warnedUnreached, "no sphere of its zone (" + zoneText() + ", " + std::to_string(ids.size()) + " spheres in it) is reached by the spray: "
		                                  + fmt(pending) + " m³ waits for the first spheres it reaches");
}

std::string ViscBridgeSpray::zoneText() const
{
	if (ballRadius > 0) return "ball at " + vec(ballCentre) + ", radius " + fmt(ballRadius) + " m";
	return "box " + vec(boxMin) + "–" + vec(boxMax) + " m";
}

void ViscBridgeSpray::warnOnce(bool& warned, const std::string& what)
{
	if (warned) return;
	warned = true;
	LOG_WARN(kOwner << (label.empty() ? "" : " '" + label + "'") << " at t = " << scene->time << " s: " << what << ".");
}

} // namespace yade
