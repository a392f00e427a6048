// The views of a scene: what each pixel shows of its layers. A view is structure (changing it
// builds another kernel), chosen by the scene (`scene { view = envelope }`) or the command
// line (`--view`), and carried to the lowering, which builds it as IR like everything else:
// no backend knows what a view is. The table below is the one list of them; a new view is
// one line here and one case in lower/Compose.cpp (docs/views.md).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace moire::sema {

enum class ViewMode {
    Pattern,  // the picture: each layer's strokes inked over the paper, in order (§3.4)
    Envelope, // the mean ink over one index period of the whole stack (Eq. 13, §4.4)
    Split,    // the pattern left of a dashed rule at the frame's middle, the envelope right
    Ratio,    // the least merit of the characters, hued by the winner's order (§4.2-4.3)
};

// The most taps the envelope averages per index period (`envelope_taps`, --envelope-taps).
constexpr double kMaxEnvelopeTaps = 1024;

struct ViewName {
    ViewMode mode;
    const char* name; // as written in a scene and on the command line
    const char* doc;
};

// Every view, in the order the documentation and messages list them.
const std::vector<ViewName>& viewNames();
// The view called `name`, if there is one.
std::optional<ViewMode> viewNamed(std::string_view name);
// The name of a view.
const char* viewName(ViewMode mode);
// "pattern, envelope or split", for messages and --help.
std::string viewList();
// Whether the view sweeps the layers' indices (and so needs each layer's phase sample).
bool viewSweeps(ViewMode mode);
// Whether the view reads the stack's winning character (lower/Characters.h), and so needs
// each layer's index field and its gradient.
bool viewReadsCharacters(ViewMode mode);

// The fringe overlay (`overlay = true`, `--overlay`, the viewer's o): the unit level sets of
// the winning character where a fringe stands, laid over any view. A switch written as a
// name: `true` or `false`.
// kSwitchNames[0] is off, [1] on.
inline constexpr const char* kSwitchNames[] = {"false", "true"};
std::optional<bool> switchNamed(std::string_view name);

// How the pattern samples a layer's strokes (`filter = mean`, `--filter`, docs/filtering.md):
// at the pixel's centre with the floored stroke (point), or averaged over the pixel's
// footprint where a phase family's members are finer than the pixels (mean, the default).
// kFilterNames[i] names FilterMode i.
enum class FilterMode { Point, Mean };
inline constexpr const char* kFilterNames[] = {"point", "mean"};
std::optional<FilterMode> filterNamed(std::string_view name);
// "point or mean", for messages and --help.
std::string filterList();

} // namespace moire::sema
