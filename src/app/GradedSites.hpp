#pragma once
// Graded spacing (a [[body]]'s grading table): the body is laid in layers about its reference,
// each a lattice of one spacing and one particle thick. Layers of the body's spacing s0 reach
// `within` of the reference; each layer beyond is `ratio` times thicker than the one before, up
// to `max_spacing`. A layer's particles are spaced as thick as it is (along a plane, round a
// line or a point), so the spacing is isotropic everywhere and the layers stack without gaps or
// overlaps along the reference's normal: a particle's nearest neighbor across a transition is
// at least its own layer's spacing away, and no point of the body is farther than ~0.9 of the
// local spacing from a particle (tests/unit/app/test_graded_sites.cpp).
#include "BodyShape.hpp"

#include <vector>

namespace spall::app::sites {

// Layer j covers distances [start, start + thickness) from the reference.
struct Layer {
  double start, thickness;
};

// The layers from the reference out to distance `end` (the last one reaches it or beyond).
std::vector<Layer> gradedLayers(double s0, double within, double ratio, double smax, double end);

// Stretches the graded layers (those beyond `within`; all of them when none is) so that the
// last one ends exactly at `end`, dropping the last layer if that stretches less. A box's face
// across the reference's normal then holds whole layers, as a uniform box holds whole cells.
void fitLayers(std::vector<Layer>& layers, double within, double s0, double end);

// The sites of a graded body (run.resolution applied; rz: the half-plane's, r > 0).
template <int Dim> std::vector<Site<Dim>> gradedSites(const Deck& deck, const BodyConfig& body);

// A DeckError when the layers out to the far side of the body would be more than 1e8 (a
// reference far from the body, or a maximum spacing far below the distance).
template <int Dim> void checkGradedLayers(const Deck& deck, const BodyConfig& body);

// An upper bound of the sites gradedSites makes, from the layers alone (the memory check).
template <int Dim> double gradedSiteEstimate(const Deck& deck, const BodyConfig& body);

} // namespace spall::app::sites
