// biarc_program.cpp — the light modal reading of `pcnc biarc`. See biarc_program.hpp.
#include "biarc_program.hpp"

#include <cmath>
#include <string_view>

#include "gcode/diagnostics.hpp"
#include "gcode/lexer.hpp"
#include "gcode/parser.hpp"
#include "geometry/plane.hpp"

namespace pcnc {
namespace {

constexpr char kAxis[3] = {'X', 'Y', 'Z'};

bool has_comment(std::string_view s) { return s.find('(') != std::string_view::npos || s.find(';') != std::string_view::npos; }

// The line without its comments: '#' or '[' left are parameters or expressions.
std::string code_part(std::string_view s) {
  std::string out;
  int depth = 0;
  for (char c : s) {
    if (c == ';' && depth == 0) break;
    if (c == '(') ++depth;
    if (depth == 0) out += c;
    if (c == ')' && depth > 0) --depth;
  }
  return out;
}

int code(const ParsedLine& p, int group) { return p.g[static_cast<std::size_t>(group)]; }

// Follows the modal and position effects of one parsed line (a file tool's view: what
// moves the program position, and what makes it unknown).
void follow(const ParsedLine& p, BiarcModal& m) {
  const int units = code(p, kGUnits);
  if (units == 200) m.scale = 25.4;
  if (units == 210) m.scale = 1.0;
  const int dist = code(p, kGDistance);
  if (dist == 900) m.incremental = false;
  if (dist == 910) m.incremental = true;
  const int arcd = code(p, kGArcDistance);
  if (arcd == 901) m.arc_absolute = true;
  if (arcd == 911) m.arc_absolute = false;
  const int plane = code(p, kGPlane);
  if (plane == 170) m.normal = 2;
  if (plane == 180) m.normal = 1;
  if (plane == 190) m.normal = 0;
  const int fm = code(p, kGFeedMode);
  if (fm == 930) m.inverse_time = true;
  if (fm == 940 || fm == 950) m.inverse_time = false;
  const int comp = code(p, kGCutterComp);
  if (comp == 400) m.comp = 0;
  if (comp == 410 || comp == 411) m.comp = 1;
  if (comp == 420 || comp == 421) m.comp = -1;
  if (p.has('F')) m.feed = p.get('F');
  if (code(p, kGMotion) >= 0) m.motion = code(p, kGMotion);
  // offsets that change what program coordinates mean: the position is no longer known
  if (code(p, kGCoordSystem) >= 0 || code(p, kGToolLength) >= 0) m.known = {false, false, false};
  const int nm = code(p, kGNonModal);
  bool axes = false;
  for (char a : kAxis) axes = axes || p.has(a);
  if (nm == 920) {  // G92: the current point gets the given coordinates
    for (int a = 0; a < 3; ++a)
      if (p.has(kAxis[a])) m.pos[static_cast<std::size_t>(a)] = p.get(kAxis[a]) * m.scale, m.known[static_cast<std::size_t>(a)] = true;
    return;
  }
  if (nm == 280 || nm == 300 || nm == 530 || nm == 921 || nm == 922 || nm == 923 || nm == 520 || nm == 100) {
    m.known = {false, false, false};  // G28/G30/G53 moves, G92.x, G52, G10: left to the machine
    return;
  }
  const bool cycle = m.motion >= 730 && m.motion <= 890 && m.motion != 800;
  if (cycle && axes) {
    m.known = {false, false, false};  // canned cycles end on their R or initial level
    return;
  }
  if (!axes || m.motion < 0 || m.motion == 800) return;
  for (int a = 0; a < 3; ++a) {
    if (!p.has(kAxis[a])) continue;
    const auto i = static_cast<std::size_t>(a);
    const double v = p.get(kAxis[a]) * m.scale;
    if (m.incremental) {
      m.pos[i] += v;
    } else {
      m.pos[i] = v;
      m.known[i] = true;
    }
  }
}

}  // namespace

std::vector<BiarcLine> read_biarc_program(const std::string& text) {
  std::vector<BiarcLine> out;
  BiarcModal m;
  bool opaque = false, in_nurbs = false;
  bool g5_series = false;  // the last move was a G5: a G5 without I and J continues it
  Vec3 g5_next{};          // that G5's P Q reversed (mm): the next one's first offset
  std::size_t at = 0;
  int number = 0;
  while (at < text.size()) {
    std::size_t nl = text.find('\n', at);
    if (nl == std::string::npos) nl = text.size();
    BiarcLine l;
    l.text = text.substr(at, nl - at);
    l.number = ++number;
    l.before = m;
    at = nl + 1;
    std::string_view body = l.text;
    if (!body.empty() && body.back() == '\r') body.remove_suffix(1);
    LexedLine lexed;
    ParsedLine parsed;
    DiagnosticSink sink;
    const bool ok = !opaque && lex_line(body, l.number, lexed, sink, nullptr) && parse_line(lexed, l.number, parsed, sink);
    const std::string codes = code_part(body);
    if (!ok || lexed.assignment_count > 0 || lexed.oword.kind != OKind::kNone || codes.find('#') != std::string::npos ||
        codes.find('[') != std::string::npos) {
      opaque = true;
      l.kind = BiarcLineKind::kOpaque;
      l.after = m;
      out.push_back(std::move(l));
      continue;
    }
    const int motion = code(parsed, kGMotion);
    l.explicit_motion = motion >= 0;
    bool axes = false;
    for (char a : kAxis) axes = axes || parsed.has(a);
    l.uses_modal_motion = axes && motion < 0 && code(parsed, kGNonModal) < 0;
    l.has_feed = parsed.has('F');
    const auto pa = plane_axes(m.normal);
    const char a0 = kAxis[pa[0]], a1 = kAxis[pa[1]], an = kAxis[m.normal];
    l.has_plane_axes = parsed.has(a0) && parsed.has(a1);
    // letters other than the three axes, F and N, and any G or M word but the motion one
    std::uint32_t others = parsed.present & ~((1u << ('X' - 'A')) | (1u << ('Y' - 'A')) | (1u << ('Z' - 'A')) |
                                               (1u << ('F' - 'A')) | (1u << ('N' - 'A')) | (1u << ('P' - 'A')) |
                                               (1u << ('L' - 'A')));
    const bool only_motion_g = (parsed.g_groups & ~(1u << kGMotion)) == 0 && parsed.m_groups == 0;
    const bool plain = others == 0 && only_motion_g && !has_comment(body) && !lexed.block_delete &&
                       lexed.message == MessageKind::kNone;
    // a G5 or G5.1 line, by its own G word or by the modal motion mode
    const bool spline_line = motion == 50 || motion == 51 || (motion < 0 && (m.motion == 50 || m.motion == 51) && axes);
    if (in_nurbs) {
      if (motion == 53 && plain && !axes && !parsed.has('P') && !parsed.has('L')) {
        l.kind = BiarcLineKind::kNurbsEnd;
        in_nurbs = false;
      } else if (motion < 0 && plain && l.has_plane_axes && !parsed.has(an) && parsed.has('P') && !parsed.has('L')) {
        l.kind = BiarcLineKind::kNurbsPoint;
        l.weight = parsed.get('P');
      } else {
        in_nurbs = motion == 52 || (motion < 0 && (axes || parsed.has('P')));  // still inside, not rewritable
        if (motion == 53) in_nurbs = false;
      }
    } else if (motion == 52) {
      in_nurbs = true;
      if (plain && !parsed.has(an) && (l.has_plane_axes || !axes)) {
        l.kind = BiarcLineKind::kNurbsStart;
        l.weight = parsed.has('P') ? parsed.get('P') : 1.0;
        l.order = parsed.has('L') ? static_cast<int>(std::lround(parsed.get('L'))) : 3;
      }
    } else if (spline_line) {
      // G5 / G5.1, LinuxCNC's rules (host/gcode/interpreter_spline.cpp): G17 only, no Z, I and J
      // together, G5 with P and Q, a G5 without I J only right after a G5
      const bool cubic = motion == 50 || (motion < 0 && m.motion == 50);
      const std::uint32_t spline_words = (1u << ('X' - 'A')) | (1u << ('Y' - 'A')) | (1u << ('F' - 'A')) | (1u << ('N' - 'A')) |
                                         (1u << ('I' - 'A')) | (1u << ('J' - 'A')) | (1u << ('P' - 'A')) | (1u << ('Q' - 'A'));
      const bool words_ok = (parsed.present & ~spline_words) == 0 && only_motion_g && !has_comment(body) && !lexed.block_delete &&
                            lexed.message == MessageKind::kNone;
      const bool has_ij = parsed.has('I') && parsed.has('J');
      l.spline_continuation = cubic && !parsed.has('I') && !parsed.has('J');
      bool valid = words_ok && m.normal == 2 && parsed.has('I') == parsed.has('J') && !m.inverse_time;
      if (cubic) {
        valid = valid && parsed.has('P') && parsed.has('Q') && (has_ij || g5_series);
      } else {
        valid = valid && has_ij && !parsed.has('P') && !parsed.has('Q');
      }
      if (valid) {
        l.kind = BiarcLineKind::kSpline;
        l.spline_degree = cubic ? 3 : 2;
        l.spline_c1 = has_ij ? Vec3{parsed.get('I') * m.scale, parsed.get('J') * m.scale, 0.0} : g5_next;
        if (cubic) l.spline_c2 = Vec3{parsed.get('P') * m.scale, parsed.get('Q') * m.scale, 0.0};
      }
      g5_series = valid && cubic;
      if (g5_series) g5_next = -1.0 * l.spline_c2;
    } else {
      const bool g1 = motion == 10 || (motion < 0 && m.motion == 10);
      bool normal_unchanged = !parsed.has(an);
      if (parsed.has(an)) {
        const auto n = static_cast<std::size_t>(m.normal);
        normal_unchanged = m.incremental ? parsed.get(an) == 0.0 : (m.known[n] && parsed.get(an) * m.scale == m.pos[n]);
      }
      if (g1 && plain && !parsed.has('P') && !parsed.has('L') && (parsed.has(a0) || parsed.has(a1)) && normal_unchanged)
        l.kind = BiarcLineKind::kG1;
    }
    if (l.kind != BiarcLineKind::kSpline && !spline_line &&
        (axes || code(parsed, kGNonModal) >= 0 || (motion >= 0 && motion != 800)))
      g5_series = false;  // another move (or what may be one) ends a G5 series
    follow(parsed, m);
    l.after = m;
    out.push_back(std::move(l));
  }
  return out;
}

}  // namespace pcnc
