#pragma once
// Where the renderers put the wall (private to tools/phantom/src): the plain
// scene (renderer.cpp) and the room (room.cpp) draw the same one.

namespace spinewatch::phantom {

// The wall stands this far behind the subject (the world origin), seen from
// either camera; the floor is y = 0.
inline constexpr double kWallBehindMm = 1500;

}  // namespace spinewatch::phantom
