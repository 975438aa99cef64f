#pragma once
// Viewer scripts (--script FILE): camera moves and setting changes replayed at given frames, for
// tests and demos. One command per line, '#' starts a comment:
//   FRAME orbit YAW PITCH     turn the orbit camera (degrees)
//   FRAME zoom FACTOR         distance *= FACTOR
//   FRAME pan DX DY           move the target (units of the distance)
//   FRAME fly X Y Z           move the camera (camera space: x right, y up, z back; world units), as WASD/QE
//   FRAME camera N|NAME       switch to a scene camera
//   FRAME frame               frame the whole scene
//   FRAME effects LIST        as --effects
//   FRAME set KNOB=VALUE      as --set
//   FRAME path auto|forward|deferred
//   FRAME screenshot OUT.png  the rendered image (without the UI)
//   FRAME reference MODE|off [MS]  reference mode: path|direct|whitted|ao refines in the
//                             background for MS (default 40) of each frame
//   FRAME show VIEW           raster|reference|split|flip|difference
//   FRAME inspect NAME [CHANNEL SCALE LAYER]  a frame-graph buffer (viewer panel names), or "off"
//   FRAME animation N|NAME|none  choose the animation (none: the rest pose); its time goes to 0
//   FRAME time T              scrub to T seconds (clamped to the animation's duration)
//   FRAME play                play from the current time (at the speed, looping unless told)
//   FRAME pause               stop at the current time (the pose stays, nothing is posed again)
//   FRAME speed X             playback speed, 0.1..4
//   FRAME loop on|off         wrap at the end, or stop there
//   FRAME variant NAME|INDEX|default  the KHR_materials_variants variant (as --variant), live
//   FRAME adaptive on|off|reduced [TARGET_MS]  adaptive quality (viewer/adaptive_quality.hpp):
//                             on: moving frames are cheaper; off: every frame at full quality;
//                             reduced: every frame at the reduced level (full size), e.g. to
//                             compare it. TARGET_MS (1..10000, default 100): the moving frames'
//                             target time. Scripted runs start with it off.
//   FRAME budget E|off        the error budget (viewer/budget_mode.hpp), as --error-budget E:
//                             E in (0, 1]; the settings are chosen from this frame's view (and
//                             again at each new E); when no raster candidate is predicted within
//                             E the reference mode traces the view (path, shown as the
//                             reference); off gives back the settings and reference from before
//   FRAME quit
#include <filesystem>
#include <string>
#include <vector>

namespace candela::viewer {

struct ScriptCommand {
    int frame = 0;
    std::string verb;
    std::vector<std::string> args;
    int line = 0;
};

// Throws candela::Error (bad_input) naming FILE:LINE for unknown verbs or bad arguments.
std::vector<ScriptCommand> load_script(const std::filesystem::path& file);

}  // namespace candela::viewer
