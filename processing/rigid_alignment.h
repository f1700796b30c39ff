#pragma once

#include "frame/camera_model.h"
#include "frame/frame.h"

#include <array>
#include <cstddef>

// How well two depth cameras' clouds agree through the transform between them, and the point-to-plane ICP
// that refines that transform (issue 32, item 3). Pure CPU; doubles for every sum.
//
// Association is projective, as KinectFusion's: a point of cloud A, moved into B's frame, is paired with the
// sample of B's depth map at the pixel it projects to, so no search structure is built and one pass over A's
// (decimated) samples associates everything.
namespace dc::processing {

// One depth map (0, NaN or inf: no measurement) and the pinhole intrinsics of its size: a cloud in its
// camera's frame (OpenCV axes, meters).
struct DepthCloud {
    const frame::DepthData* depth = nullptr;
    frame::Intrinsics intrinsics;
    // A depth map that matches its valid intrinsics.
    bool usable() const;
};

struct AssociationParams {
    // Every stride-th sample of A in each direction: 2 keeps a quarter of them, plenty for six unknowns.
    int stride = 2;
    // B's normal at a pixel is that of the plane fitted to the samples of the (2 span + 1)^2 window around it
    // (the least-squares tangents' cross product): 3 averages the depth noise over 49 samples.
    int normalSpanPixels = 3;
    // A window sample whose depth differs from the centre's by more than this fraction per pixel of distance
    // lies across a depth edge (or is a mixed pixel there) and is left out of the fit. A surface seen at 20
    // degrees from grazing changes depth by about 1 % per pixel at 320x240, so 4 % keeps such surfaces and
    // drops real edges.
    double maxDepthJumpPerPixel = 0.04;
};

struct OverlapParams {
    AssociationParams association;
    // A pair whose points lie farther apart than this is not the same surface: outside the overlap.
    double maxDistanceMeters = 0.05;
};

// The overlap consistency figure: how far A's points lie from B's surface where the two overlap.
struct OverlapFigure {
    double medianMm = 0.0;        // median |point-to-plane distance|; 0 without overlap
    double overlapFraction = 0.0; // count / candidates
    std::size_t count = 0;        // A samples paired with B's surface
    std::size_t candidates = 0;   // A samples with a valid depth (after decimation)
};

// A's points moved into B's frame by aToB, projected into B's depth map; a point overlaps where it lands on a
// valid B sample that has a normal and lies within params.maxDistanceMeters. Not usable clouds: all zero.
OverlapFigure overlapConsistency(const DepthCloud& a, const DepthCloud& b, const frame::RigidTransform& aToB,
                                 const OverlapParams& params = {});

enum class IcpStatus {
    Ok,           // refined along every direction
    Degenerate,   // the overlap leaves some motion unconstrained (one plane lets it slide): refined along
                  // the constrained directions only, left as seeded along the others
    TooFewPoints, // not enough overlap to estimate a motion: the seed is returned unchanged
    InvalidInput, // an unusable cloud, or a seed whose rotation is not a rotation: the seed unchanged
};
const char* toString(IcpStatus status);

struct IcpParams {
    // Association for the iterations; figure also gives the before/after residual's gate, so that they are
    // the overlap figure shown beside it.
    OverlapParams figure;
    // The association gate shrinks geometrically from the first distance (it must reach across the seed's
    // error) to the last (a few noise widths, so that other surfaces stop pulling).
    double firstMaxDistanceMeters = 0.10;
    double lastMaxDistanceMeters = 0.02;
    double distanceShrink = 0.7;
    // A weakly constrained direction converges slowly (the pairs that pin it are the last to come within the
    // robust weight's reach): the synthetic desk's sideways motion needs about 30 iterations from 3 degrees
    // off.
    int maxIterations = 50;
    // Fewer pairs than this cannot be trusted to pin six unknowns.
    std::size_t minPoints = 100;
    // Eigenvalues of the normal equations (translation in meters, rotation scaled by the cloud's radius so
    // both are lengths) below this fraction of the largest are unconstrained directions. A plane's free
    // motions read about 1e-4 (the normals' noise, not the geometry, keeps them above 0); the synthetic desk
    // scene, whose only hold on sideways motion is an apple and a book, reads 0.015.
    double minConditionRatio = 0.003;
    // Converged: an update smaller than both, once the gate has shrunk to its last distance.
    double stopRotationDegrees = 1e-3;
    double stopTranslationMeters = 1e-5;
};

struct IcpResult {
    IcpStatus status = IcpStatus::InvalidInput;
    frame::RigidTransform aToB; // refined (the seed where nothing could be refined)
    // refined = correction * seed: what the refinement changed, in B's frame.
    frame::RigidTransform correction;
    double correctionDegrees = 0.0;
    double correctionMm = 0.0;
    OverlapFigure before;    // with the seed
    OverlapFigure after;     // with the refined transform
    std::size_t inliers = 0; // pairs with a non-zero robust weight in the last iteration
    int iterations = 0;
    bool converged = false;
    // Smallest over largest eigenvalue of the last iteration's normal equations (1: every direction as well
    // constrained as the best; 0: a free direction), and how many directions were solved for.
    double conditionRatio = 0.0;
    int constrainedDirections = 0;
};

// Point-to-plane ICP from `seed`: each iteration re-associates, weighs the residuals with Tukey's biweight
// (its scale from their median absolute deviation, so mixed pixels and the other side of an edge drop out),
// solves a 6x6 Gauss-Newton system for a small rotation and translation, and applies it along the constrained
// directions only.
IcpResult refineAlignment(const DepthCloud& a, const DepthCloud& b, const frame::RigidTransform& seed,
                          const IcpParams& params = {});

// The angle of a transform's rotation (composing and inverting transforms: frame::compose, frame::inverse).
double rotationDegrees(const frame::RigidTransform& t);
// The transform from camera A's frame to camera B's, given both cameras' camera-to-world poses.
frame::RigidTransform relativeTransform(const frame::Pose& a, const frame::Pose& b);

} // namespace dc::processing
