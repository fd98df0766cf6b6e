#pragma once
// The value a scene's frame loop carries from frame to frame (rigid.scene -> rigid.frame ->
// export.animation). The recorded frames form a chain shared between states, so carrying the
// animation costs one frame per iteration, not the whole history; pieces and fracture runs are
// copied only when they change. The simulation itself (Bullet world, fracture models) is mutable
// and owned by the loop: only rigid.frame touches it, and consumers of LOOP.each read the
// recorded, immutable parts only (they run while the next frame is computed).
#include "nodes/rigid/animation.hpp"
#include "nodes/rigid/scene_simulation.hpp"

#include <memory>
#include <vector>

namespace cf::rigid {

struct RecordedFrame {
    AnimationFrame frame;
    std::shared_ptr<const RecordedFrame> previous;  // null for frame 0
};

struct SceneState {
    std::shared_ptr<SceneSimulation> simulation;
    std::shared_ptr<const RecordedFrame> last;                  // the latest frame
    std::shared_ptr<const std::vector<AnimationPiece>> pieces;  // every piece so far
    std::shared_ptr<const std::vector<FractureRunRecord>> runs;
    double frame_rate = 50;
    int frame = 0;
    double rigid_seconds = 0, fracture_seconds = 0;  // summed over the frames so far (Table 3's t_rb, t_f)
};

// Records the simulation's current frame on top of `previous` (null for the first).
SceneState record_frame(const std::shared_ptr<SceneSimulation>& sim, const SceneState* previous);

// The whole animation up to the state's frame (pieces' last frames closed at pieces that are gone).
Animation animation_of(const SceneState& s);

}  // namespace cf::rigid

CF_GRAPH_TYPE(cf::rigid::SceneState, "SceneState");
CF_GRAPH_TYPE(cf::rigid::ImpactRun, "ImpactRun");
