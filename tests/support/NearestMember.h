// An independent reference for the stdlib phase families: each family's phase written out
// from Table 1 of the spec in C++, and the true Euclidean distance from a point to the
// nearest member curve, found by a numeric search that never looks at a gradient.
//
// The renderer's distance is Eq. 5, |index - nearest| / |grad index|, with the gradient from
// forward-mode AD. Nothing here uses that formula: the search walks rays out of the point,
// finds where the phase passes a member's level, and keeps the closest such point. So where
// the two agree, Eq. 5 really is the distance; where they differ, the difference is the
// error of the eikonal approximation (or of a corner), not of the test.
#pragma once

#include <functional>
#include <optional>
#include <string>

namespace moire::test {

// One stdlib family at one parameter setting, in the layer's own frame (x, y after origin
// and rotation). `phi` takes a reference angle: an angular family measures theta on the
// branch (ref - pi, ref + pi], so that a search around one point never crosses a branch cut
// (the spiral's phase jumps by a whole number of members across atan2's cut; the members
// themselves are continuous). With ref = 0 it is the principal atan2 branch, as the
// renderer's `theta` is.
struct RefFamily {
    std::string name;
    std::function<double(double x, double y, double ref)> phi;
    std::function<double(double x, double y)> gradNorm; // Table 1's |grad phi| column
    std::optional<int> first;                           // members n >= first only
    // A concentric family's phase is least (0) at the centre alone, so its member of level 0
    // is a single point, which the phase touches without crossing: the search adds it.
    bool pointCentre = false;
};

// The families of stdlib/families.moire, from Table 1 (angles in radians).
RefFamily refLines(double angle);
RefFamily refCircles();
RefFamily refSquares();
RefFamily refTriangles();
RefFamily refHexagons();
RefFamily refNgon(int sides);
RefFamily refWave(double amplitude, double frequency, double shift);
RefFamily refParabola(double bend);
RefFamily refHyperbola();
RefFamily refSpiral(int arms, double spacing); // arms already a whole number

// A layer: the family, its spacing s and phase offset, and its frame in the world.
struct RefLayer {
    RefFamily family;
    double spacing = 10.0, phase = 0.0;
    double originX = 0.0, originY = 0.0, rotation = 0.0; // rotation in radians

    // World point -> the layer's own frame: q = Rot(-rotation) (p - origin), and back.
    void toLocal(double wx, double wy, double& lx, double& ly) const;
    void toWorld(double lx, double ly, double& wx, double& wy) const;
    // The fractional index (phi - phase) / s at a world point, on the principal branch.
    double index(double wx, double wy) const;
};

// The scene text of one layer of stdlib family `family` with parameters `args` (scene
// syntax, e.g. "sides = 7"), at this layer's spacing, phase, origin and rotation.
std::string layerSource(const std::string& family, const std::string& args, const RefLayer& layer);

struct Nearest {
    bool found = false;        // false: no member within the search radius
    double distance = 0.0;     // Euclidean distance to the nearest member
    double lx = 0.0, ly = 0.0; // the nearest point on it, in the layer frame
    long member = 0;           // its index n (the level is n s + phase)
};

// The nearest member to world point (wx, wy) within `radius` world units.
Nearest nearestMember(const RefLayer& layer, double wx, double wy, double radius);

// The curvature (1 / radius) of the member through the layer-frame point `at`, from the
// implicit-curve formula on Table 1's phase with finite-difference derivatives.
double memberCurvature(const RefLayer& layer, const Nearest& at);

} // namespace moire::test
