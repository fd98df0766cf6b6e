#include "nodes/rigid/scene_state.hpp"

namespace cf::rigid {

SceneState record_frame(const std::shared_ptr<SceneSimulation>& sim, const SceneState* previous) {
    SceneState s;
    s.simulation = sim;
    s.frame = sim->frame();
    s.frame_rate = sim->settings().frame_rate;
    auto rec = std::make_shared<RecordedFrame>();
    rec->frame = sim->current_frame();
    rec->previous = previous ? previous->last : nullptr;
    s.last = std::move(rec);
    const bool same_pieces = previous && previous->pieces->size() == sim->pieces().size() &&
                             (previous->pieces->empty() || previous->pieces->back().last_frame == sim->pieces().back().last_frame);
    // Parents are closed (last_frame set) when they break, which always adds pieces: a changed
    // count is the only change to look for.
    s.pieces = same_pieces ? previous->pieces : std::make_shared<const std::vector<AnimationPiece>>(sim->pieces());
    s.runs = previous && previous->runs->size() == sim->runs().size()
                 ? previous->runs
                 : std::make_shared<const std::vector<FractureRunRecord>>(sim->runs());
    if (previous) {
        s.rigid_seconds = previous->rigid_seconds;
        s.fracture_seconds = previous->fracture_seconds;
    }
    return s;
}

Animation animation_of(const SceneState& s) {
    // A fragment that breaks again within the frame it was made in is never seen: it has no pose
    // in any frame. Leave it out, and give its fragments its own parent (their visible ancestor).
    const std::vector<AnimationPiece>& all = *s.pieces;
    std::vector<int> index(all.size(), -1);
    Animation a;
    a.frame_rate = s.frame_rate;
    for (std::size_t i = 0; i < all.size(); ++i) {
        const AnimationPiece& p = all[i];
        if (p.last_frame != -1 && p.last_frame < p.first_frame) continue;
        AnimationPiece q = p;
        int parent = p.parent;
        while (parent >= 0 && index[static_cast<std::size_t>(parent)] < 0) parent = all[static_cast<std::size_t>(parent)].parent;
        q.parent = parent >= 0 ? index[static_cast<std::size_t>(parent)] : -1;
        index[i] = static_cast<int>(a.pieces.size());
        a.pieces.push_back(std::move(q));
    }
    std::vector<const RecordedFrame*> chain;
    for (const RecordedFrame* r = s.last.get(); r; r = r->previous.get()) chain.push_back(r);
    a.frames.reserve(chain.size());
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        AnimationFrame f;
        f.time = (*it)->frame.time;
        for (const auto& [i, pose] : (*it)->frame.poses)
            if (index[static_cast<std::size_t>(i)] >= 0) f.poses.emplace_back(index[static_cast<std::size_t>(i)], pose);
        a.frames.push_back(std::move(f));
    }
    return a;
}

}  // namespace cf::rigid
