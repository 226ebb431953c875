// glTF 2.0 animations: keyframe samplers and the node properties they drive, evaluated as the
// specification's Appendix C says (docs/animation.md).
#pragma once

#include <dhdr/common/frame_limits.h>
#include <dhdr/common/param_table.h>
#include <string>
#include <vector>

namespace dhdr {

enum class Interpolation { Linear, Step, CubicSpline };
enum class AnimatedProperty { Translation, Rotation, Scale, Weights };

// One sampler: key times and the values at them.
struct AnimationSampler {
    Interpolation interpolation = Interpolation::Linear;
    std::vector<float> times; // seconds, finite and strictly increasing (checked on loading)
    // `components` numbers per key; CUBICSPLINE: in-tangent, value, out-tangent per key.
    std::vector<float> values;
    int components = 0;    // 3 translation and scale, 4 rotation (x y z w), the targets for weights
    bool rotation = false; // values are quaternions: slerp (shortest arc), normalised results

    // The value at time `t` into `out` (`components` numbers): before the first key the first
    // value, after the last the last (Appendix C: "clamped to the nearest end"). A time that
    // rounds to a key's float is that key's time (a STEP holds from its key's frame on).
    void evaluate(double t, double* out) const;
};

struct AnimationChannel {
    int sampler = 0; // index into Animation::samplers
    int node = 0;    // index into the file's nodes
    AnimatedProperty property = AnimatedProperty::Translation;
};

struct Animation {
    std::string name; // the file's, or "animation N" when it gives none
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    double start = 0.0, end = 0.0; // the first and last key time of any sampler, seconds
    // Why the animation cannot be played (a sampler whose times decrease, a count that does not
    // match...), naming the sampler or channel; empty when it can.
    std::string problem;

    double duration() const { return end - start; }
};

// What the tools and the Python module say when options of time (--frame, --time, --fps,
// --frames) meet a scene that does not move: also true of a file whose animations dhdr cannot
// play (Collada, FBX, glTF 1.0), which the loader names in a warning of its own.
inline constexpr const char* kNoAnimationPlayed = "the scene has no animation that dhdr plays";

// The animations `selection` names among `animations`: "" (the first, as glTF viewers play),
// "all", an index (a whole number, before a name of the same digits), or a name. False with
// `error` listing the file's animations when none matches, or naming the problem of one that
// cannot be played.
bool selectAnimations(const std::vector<Animation>& animations, const std::string& selection,
                      std::vector<int>& chosen, std::string& error);

// The moment of the animation a render shows (docs/animation.md): frame N shows time N / fps,
// frame 0 time 0; a time given instead of a frame shows that time.
struct MomentChoice {
    double fps = 24.0;
    double time = 0.0; // seconds
    int frame = 0;
};

// MomentChoice's ranges, and the options of dhdr-gbuffer and dhdr-probes and keywords of
// dhdr.render_gbuffer() and Scene.posed() that set them.
inline constexpr FloatParam<MomentChoice, double> kMomentFloatTable[] = {
    {"--fps",
     "fps",
     &MomentChoice::fps,
     {0.0, 1e6, true},
     "F",
     "frames a second: frame N shows the animation at time N / F"},
    {"--time",
     "time",
     &MomentChoice::time,
     {-1e9, 1e9},
     "SECONDS",
     "the scene's animation at this time, in seconds, into the one output (default: the "
     "frame's time)"},
};
inline constexpr IntParam<MomentChoice> kMomentIntTable[] = {
    {"--frame", &MomentChoice::frame, int(kMinFrame), int(kMaxFrame), "N",
     "frame N of the scene's animation (time N / fps), into the one output (-o without a frame "
     "pattern; default: the frames of --frames, else 0)",
     "frame"},
};

} // namespace dhdr
