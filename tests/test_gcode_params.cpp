// test_gcode_params.cpp — parameters, expressions, O-word control flow, subprograms and
// messages as LinuxCNC's RS274NGC interpreter defines them (issue 12), through the front end
// (list_moves: what `pcnc check --print-moves` prints).
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <string>

#include <fstream>

#include "gcode_listing.hpp"
#include "subprocess.hpp"
#include "test_paths.hpp"

namespace pcnc::test {
namespace {

double x_of(const Listing& l, std::size_t i) { return l.moves.at(i).end[0]; }
double y_of(const Listing& l, std::size_t i) { return l.moves.at(i).end[1]; }

// ---- parameters and expressions ----

TEST(GcodeParams, ValuesOnALineAreReadBeforeItsAssignments) {
  // RS274NGC: every value is read first, then the line's assignments take effect.
  const Listing l = list_program("#1=1\n#1=2 #2=#1\nG0 X#2 Y#1\n#3=7 G0 X#3\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 2u);
  EXPECT_DOUBLE_EQ(x_of(l, 0), 1.0) << "#2 got the old #1";
  EXPECT_DOUBLE_EQ(y_of(l, 0), 2.0);
  EXPECT_DOUBLE_EQ(x_of(l, 1), 0.0) << "#3 is read before '#3=7' on the same line (unset: 0)";
}

TEST(GcodeParams, UnsetNumberedIsZeroUnsetNamedIsAnError) {
  const Listing a = list_program("G0 X#77 Y[#78+1]\nM2\n");
  ASSERT_TRUE(a.result.ok) << a.first_error();
  EXPECT_DOUBLE_EQ(x_of(a, 0), 0.0);
  EXPECT_DOUBLE_EQ(y_of(a, 0), 1.0);
  const Listing b = list_program("G0 X1\nG0 X#<depth>\nM2\n");
  EXPECT_FALSE(b.result.ok);
  EXPECT_NE(b.first_error().find("test.ngc:2:5: error: named parameter #<depth> is not defined"), std::string::npos)
      << b.first_error();
}

TEST(GcodeParams, NamesIgnoreCaseAndSpaces) {
  const Listing l = list_program("#<Tool Depth>=3\nG0 X#<tooldepth> Y#<TOOL_DEPTH>\nM2\n");
  EXPECT_FALSE(l.result.ok) << "tool_depth is another name";
  const Listing ok = list_program("#<Tool Depth>=3\nG0 X#<tooldepth> Y#<TOOLDEPTH>\nM2\n");
  ASSERT_TRUE(ok.result.ok) << ok.first_error();
  EXPECT_DOUBLE_EQ(x_of(ok, 0), 3.0);
  EXPECT_DOUBLE_EQ(y_of(ok, 0), 3.0);
}

TEST(GcodeParams, IndirectParameters) {
  const Listing l = list_program("#1=5\n#5=2.5\nG0 X##1 Y#[#1*2-5]\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_DOUBLE_EQ(x_of(l, 0), 2.5);
  EXPECT_DOUBLE_EQ(y_of(l, 0), 2.5);
}

struct ExprCase {
  const char* expr;
  double value;
};
class Expressions : public ::testing::TestWithParam<ExprCase> {};

TEST_P(Expressions, EvaluateAsLinuxCnc) {
  const Listing l = list_program(std::string("#1=3\n#<_g>=4\nG0 X") + GetParam().expr + "\nM2\n");
  ASSERT_TRUE(l.result.ok) << GetParam().expr << ": " << l.first_error();
  EXPECT_NEAR(x_of(l, 0), GetParam().value, 1e-9) << GetParam().expr;
}

INSTANTIATE_TEST_SUITE_P(
    Table, Expressions,
    ::testing::Values(ExprCase{"[1+2*3]", 7}, ExprCase{"[2**3*2]", 16}, ExprCase{"[2*3**2]", 18},
                      ExprCase{"[-2**2]", 4},  // the sign belongs to the operand
                      ExprCase{"[10-4-3]", 3}, ExprCase{"[12/3/2]", 2}, ExprCase{"[7 MOD 3]", 1},
                      ExprCase{"[-7 MOD 3]", 2},  // never negative
                      ExprCase{"[1+2 GT 2]", 1}, ExprCase{"[2 LT 1+2]", 1}, ExprCase{"[1 OR 0 AND 0]", 0},
                      ExprCase{"[1 XOR 1]", 0}, ExprCase{"[0 XOR 2]", 1}, ExprCase{"[0.1+0.2 EQ 0.3]", 1},
                      ExprCase{"[1 NE 1.0000001]", 0}, ExprCase{"[2 GE 2.0000001]", 1}, ExprCase{"[2 GT 2]", 0},
                      ExprCase{"[3 LE 2]", 0}, ExprCase{"[ATAN[1]/[1]]", 45}, ExprCase{"[ACOS[0]]", 90},
                      ExprCase{"[ASIN[1]]", 90}, ExprCase{"[COS[60]]", 0.5}, ExprCase{"[TAN[45]]", 1},
                      ExprCase{"[EXP[0]]", 1}, ExprCase{"[LN[1]]", 0}, ExprCase{"[ROUND[-2.5]]", -3},
                      ExprCase{"[FIX[-2.5]]", -3}, ExprCase{"[FUP[-2.5]]", -2}, ExprCase{"[ABS[#1-5]]", 2},
                      ExprCase{"[SQRT[#1*#1+#<_g>*#<_g>]]", 5}, ExprCase{"[EXISTS[#<_g>]]", 1},
                      ExprCase{"[EXISTS[#<nothing>]]", 0}, ExprCase{"-#1", -3}, ExprCase{"-[1+1]", -2},
                      ExprCase{"SIN[90]", 1}, ExprCase{"#<_metric>", 1}, ExprCase{"#<_absolute>", 1}));

TEST(GcodeParams, SystemParametersShowTheState) {
  // #5420-#5422: the current point in program units and the active system (with its offset).
  const Listing l = list_program(
      "G10 L2 P2 X10\nG55 G0 X1 Y2 Z3\nG20\n#1=#5420\n#2=#5421\nG21\n#3=#5220\n#4=#<_coord_system>\n"
      "G0 X#1 Y#2 Z#3\nG0 X#4\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 3u);
  EXPECT_NEAR(x_of(l, 1), 10.0 + 1.0 / 25.4, 1e-9) << "#5420 in inches after G20";
  EXPECT_NEAR(y_of(l, 1), 2.0 / 25.4, 1e-9);
  EXPECT_NEAR(l.moves[1].end[2], 2.0, 1e-9) << "#5220 = 2 (G55)";
  EXPECT_NEAR(x_of(l, 2), 10.0 + 550.0, 1e-9) << "#<_coord_system> = 550";
  EXPECT_TRUE(list_program("#5420=1\nM2\n").has_error("read-only"));
}

TEST(GcodeParams, ErrorsNameTheColumn) {
  const Listing l = list_program("G0 X[1/#9]\nM2\n");
  EXPECT_NE(l.first_error().find("test.ngc:1:7: error: division by zero"), std::string::npos) << l.first_error();
  const Listing m = list_program("G0 X[2 ** 0.5] Y[-2 ** 0.5]\nM2\n");
  EXPECT_NE(m.first_error().find("non-integer power"), std::string::npos) << m.first_error();
}

// ---- subroutines ----

TEST(GcodeSubs, ArgumentsReturnValueAndRestoredLocals) {
  const std::string p =
      "o<add> sub\n"
      "  #<sum>=[#1+#2]\n"
      "  o<add> return [#<sum>]\n"
      "  G0 X99 (never: after return)\n"
      "o<add> endsub\n"
      "#1=9\n"
      "o<add> call [2] [3]\n"
      "G0 X#<_value> Y#1\n"
      "M2\n";
  const Listing l = list_program(p);
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 1u);
  EXPECT_DOUBLE_EQ(x_of(l, 0), 5.0);
  EXPECT_DOUBLE_EQ(y_of(l, 0), 9.0) << "#1-#30 are restored after the call";
  const Listing local = list_program(
      "o<s> sub\n#<inner>=1\n#<_outer>=2\no<s> endsub\no<s> call\nG0 X#<_outer>\nG0 Y#<inner>\nM2\n");
  EXPECT_TRUE(local.has_error("#<inner> is not defined")) << "a named parameter set in a sub is local to it";
}

TEST(GcodeSubs, DefinedAfterTheProgramEndAndCalledBeforeIt) {
  const Listing l = list_program("o100 call [4]\no<two> call\nM2\no100 sub\nG0 X#1\no100 endsub\no<two> sub\nG0 Y7\no<two> endsub\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 2u);
  EXPECT_DOUBLE_EQ(x_of(l, 0), 4.0);
  EXPECT_DOUBLE_EQ(y_of(l, 1), 7.0);
  EXPECT_EQ(l.moves[0].line, 5) << "moves name the line inside the subroutine";
  EXPECT_FALSE(run_program("o100 call [4]\nM2\no100 sub\nG0 X#1\no100 endsub\n", wide_config())
                   .has_warning("after the program end"))
      << "subroutines after M2 are not stray text";
}

TEST(GcodeSubs, RecursionWorksAndItsDepthIsBounded) {
  const std::string fact =
      "o<fact> sub\n"
      "  o1 if [#1 LE 1]\n"
      "    o<fact> return [1]\n"
      "  o1 endif\n"
      "  o<fact> call [#1-1]\n"
      "  o<fact> return [#1*#<_value>]\n"
      "o<fact> endsub\n"
      "o<fact> call [5]\n"
      "G0 X#<_value>\n"
      "M2\n";
  const Listing l = list_program(fact);
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_DOUBLE_EQ(x_of(l, 0), 120.0);
  const Listing runaway = list_program("o<r> sub\no<r> call\no<r> endsub\no<r> call\nM2\n");
  EXPECT_TRUE(runaway.has_error("nested more than 64")) << runaway.first_error();
}

TEST(GcodeSubs, NestedDefinitionsAndStrayKeywordsAreRefused) {
  EXPECT_TRUE(list_program("o1 sub\no2 sub\no2 endsub\no1 endsub\nM2\n").has_error("cannot be nested"));
  EXPECT_TRUE(list_program("o1 sub\nG0 X1\nM2\n").has_error("has no endsub"));
  EXPECT_TRUE(list_program("o1 endsub\nM2\n").has_error("outside a subroutine"));
  EXPECT_TRUE(list_program("o<nowhere> call\nM2\n").has_error("unknown subroutine o<nowhere>"));
  EXPECT_TRUE(list_program("o<nowhere> call\nM2\n").has_error("or in nowhere.ngc beside it")) << "where LinuxCNC's files go";
}

TEST(GcodeSubs, FanucM98CallsASubprogramLTimes) {
  const Listing l = list_program("G91\nM98 P1000 L3\nG90 G0 X0\nM30\nO1000\nG0 X2\nM99\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.moves.size(), 4u);
  EXPECT_DOUBLE_EQ(x_of(l, 0), 2.0);
  EXPECT_DOUBLE_EQ(x_of(l, 2), 6.0);
  EXPECT_DOUBLE_EQ(x_of(l, 3), 0.0);
  const RunResult checked = run_program("G91\nM98 P1000 L3\nG90 G0 X0\nM30\nO1000\nG0 X2\nM99\n", wide_config());
  ASSERT_TRUE(checked.check.ok);
  EXPECT_FALSE(checked.has_warning("after the program end")) << "subprograms after M30 are not stray text";
  EXPECT_TRUE(run_program("G0 X1\nM30\nG0 X2\n", wide_config()).has_warning("after the program end"));
  EXPECT_TRUE(list_program("M98 P7\nM30\n").has_error("no subprogram O7"));
}

// ---- branches and loops ----

TEST(GcodeFlow, IfElseifElse) {
  for (int v = 0; v < 3; ++v) {
    const std::string p = "#1=" + std::to_string(v) +
                          "\no10 if [#1 EQ 0]\nG0 X10\no10 elseif [#1 EQ 1]\nG0 X11\no10 else\nG0 X12\no10 endif\nM2\n";
    const Listing l = list_program(p);
    ASSERT_TRUE(l.result.ok) << l.first_error();
    ASSERT_EQ(l.moves.size(), 1u) << v;
    EXPECT_DOUBLE_EQ(x_of(l, 0), 10.0 + v);
  }
}

TEST(GcodeFlow, UnreadBranchesAreNotEvaluated) {
  // A false branch may read what is not defined: it is never evaluated.
  const Listing l = list_program("o1 if [0]\nG0 X#<undefined>\no1 endif\nG0 X1\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_EQ(l.moves.size(), 1u);
}

TEST(GcodeFlow, WhileDoRepeatBreakContinue) {
  const Listing w = list_program("#1=0\no1 while [#1 LT 3]\nG0 X#1\n#1=[#1+1]\no1 endwhile\nM2\n");
  ASSERT_TRUE(w.result.ok) << w.first_error();
  ASSERT_EQ(w.moves.size(), 3u);
  EXPECT_DOUBLE_EQ(x_of(w, 2), 2.0);

  const Listing d = list_program("#1=5\no2 do\nG0 X#1\n#1=[#1+1]\no2 while [#1 LT 3]\nM2\n");
  ASSERT_TRUE(d.result.ok) << d.first_error();
  EXPECT_EQ(d.moves.size(), 1u) << "a do-loop runs once even when its condition is false";

  const Listing r = list_program("G91\no3 repeat [4]\nG0 X1\no3 endrepeat\nM2\n");
  ASSERT_TRUE(r.result.ok) << r.first_error();
  ASSERT_EQ(r.moves.size(), 4u);
  EXPECT_DOUBLE_EQ(x_of(r, 3), 4.0);

  const Listing b = list_program(
      "#1=0\no4 while [1]\n#1=[#1+1]\no5 if [#1 EQ 2]\no4 continue\no5 endif\no6 if [#1 GT 3]\no4 break\no6 endif\n"
      "G0 X#1\no4 endwhile\nG0 Y9\nM2\n");
  ASSERT_TRUE(b.result.ok) << b.first_error();
  ASSERT_EQ(b.moves.size(), 3u) << "1 and 3 (2 continued), then the move after the loop";
  EXPECT_DOUBLE_EQ(x_of(b, 0), 1.0);
  EXPECT_DOUBLE_EQ(x_of(b, 1), 3.0);
  EXPECT_DOUBLE_EQ(y_of(b, 2), 9.0);
}

TEST(GcodeFlow, ALoopThatNeverEndsIsAnErrorNotAHang) {
  MachineConfig c = wide_config();
  c.gcode.max_executed_lines = 10000;
  const Listing l = list_program("G0 X1\n#1=0\no7 while [1]\n#1=[#1+1]\no7 endwhile\nM2\n", c);
  EXPECT_FALSE(l.result.ok);
  EXPECT_NE(l.first_error().find("test.ngc:3: error: the program ran more than 10000 lines in the loop that starts here"),
            std::string::npos)
      << l.first_error();
}

TEST(GcodeFlow, AMillionIterationsInBoundedMemory) {
  // The loop runs from file positions: memory does not grow with the iterations. Under the
  // sanitizers, whose allocator keeps freed memory (the bound is not checked there), a tenth.
  const std::uint64_t iterations = test::sanitizer_build() ? 100000 : 1000000;
  const std::string p = "#1=0\no1 while [#1 LT " + std::to_string(iterations) +
                        "]\nG1 X[#1 MOD 10] F600\n#1=[#1+1]\no1 endwhile\nM2\n";
  JobOptions o;
  o.start_position = Vec3{};
  o.offset = Vec3{};
  std::uint64_t moves = 0;
  double last_x = -1.0;
  rusage before{};
  getrusage(RUSAGE_SELF, &before);
  const MoveListing r = list_moves_text(
      p, "loop.ngc", wide_config(), o,
      [&](const Move& m) {
        if (m.kind == MoveKind::kLine) {
          ++moves;
          last_x = m.end[0];
        }
      },
      nullptr);
  rusage after{};
  getrusage(RUSAGE_SELF, &after);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(moves, iterations);
  EXPECT_DOUBLE_EQ(last_x, 9.0);
#if defined(__SANITIZE_ADDRESS__) || defined(PCNC_ASAN_RUNTIME)
  // AddressSanitizer holds freed memory in its quarantine (256 MB by default), so its peak says
  // nothing of the program's: the bound is checked in the normal build.
  (void)before;
  (void)after;
#else
  EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 16 * 1024) << "kB of peak memory grown over 10^6 iterations";
#endif
}

TEST(GcodeFlow, LoopsAndCallsAcrossTheReadBufferOfAFile) {
  // A loop body and a subroutine far larger than the reader's 64 KiB buffer: the positions
  // are file offsets, re-read with a seek; inside the buffer no read happens.
  const std::string dir = make_temp_dir("gcode-flow");
  const std::string path = dir + "/big.ngc";
  std::ofstream f(path);
  f << "#1=0\nO1 while [#1 LT 3]\n";
  for (int i = 0; i < 3000; ++i) f << "(padding line " << i << " to push the loop's end past the read buffer)\n";
  f << "G0 X#1\n#1=[#1+1]\nO1 endwhile\no<far> call [7]\nM2\n";
  for (int i = 0; i < 3000; ++i) f << "(more padding " << i << " before the subroutine's definition)\n";
  f << "o<far> sub\nG0 Y#1\no<far> endsub\n";
  f.close();
  JobOptions o;
  o.start_position = Vec3{};
  o.offset = Vec3{};
  std::vector<Move> moves;
  const MoveListing r = list_moves(
      path, wide_config(), o,
      [&](const Move& m) {
        if (m.kind == MoveKind::kRapid) moves.push_back(m);
      },
      nullptr);
  ASSERT_TRUE(r.ok);
  ASSERT_EQ(moves.size(), 4u);
  EXPECT_DOUBLE_EQ(moves[2].end[0], 2.0);
  EXPECT_DOUBLE_EQ(moves[3].end[1], 7.0);
  EXPECT_EQ(moves[3].line, 6009);  // 2 + 3000 + 5 + 3000 + 2
}

TEST(GcodeSubs, ASubroutineFileBesideTheProgram) {
  // LinuxCNC: o<name> call, not defined in the program, runs name.ngc beside it.
  const std::string dir = make_temp_dir("gcode-subfile");
  std::ofstream(dir + "/main.ngc") << "#<_calls>=0\no<peck> call [2]\no<peck> call [3]\nG0 Z9\nM2\n";
  std::ofstream(dir + "/peck.ngc") << "(a subroutine file)\no<peck> sub\nG0 X#1\n#<_calls>=[#<_calls>+1]\no<peck> endsub\n";
  std::ofstream(dir + "/lost.ngc") << "o<nothere> call\nM2\n";
  JobOptions o;
  o.start_position = Vec3{};
  o.offset = Vec3{};
  std::vector<Move> moves;
  const MoveListing r = list_moves(
      dir + "/main.ngc", wide_config(), o,
      [&](const Move& m) {
        if (m.kind == MoveKind::kRapid) moves.push_back(m);
      },
      nullptr);
  ASSERT_TRUE(r.ok) << (r.diagnostics.empty() ? "" : format_diagnostic(r.diagnostics[0]));
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_DOUBLE_EQ(moves[0].end[0], 2.0);
  EXPECT_EQ(moves[0].line, 3) << "the line in peck.ngc";
  EXPECT_DOUBLE_EQ(moves[1].end[0], 3.0);
  EXPECT_DOUBLE_EQ(moves[2].end[2], 9.0);
  EXPECT_EQ(moves[2].line, 4) << "back in main.ngc";
  const MoveListing lost = list_moves(dir + "/lost.ngc", wide_config(), o, nullptr, nullptr);
  EXPECT_FALSE(lost.ok);
}

// ---- M70-M73: saving and restoring the modal state (interpreter_modal_state.cpp) ----

// The state a (DEBUG,...) line shows: units, distance mode, feed, plane, work system.
const char* kShowState = "(DEBUG,%d#<_imperial> %d#<_absolute> %.1f#<_feed> %d#<_plane> %d#5220)\n";

std::string with_state(const std::string& text) {
  std::string out;
  for (std::size_t at = 0;;) {
    const std::size_t s = text.find("SHOW\n", at);
    if (s == std::string::npos) return out + text.substr(at);
    out += text.substr(at, s - at) + kShowState;
    at = s + 5;
  }
}

// LinuxCNC's M-code reference examples: M70 ... M72 around a call that changes units,
// distance mode and feed; M73 in a subroutine restores on endsub and on a return from inside a
// loop; the motion mode is not part of the state.
TEST(GcodeModalState, M70M72AndM73RestoreTheCallersState) {
  const Listing l = list_program(with_state(
      "o<imperialsub> sub\nG20 G91 G18 G55 F5\no<imperialsub> endsub\n"
      "o<autosub> sub\nM73\nG20 G91 F7\nSHOW\no100 while [1]\no<autosub> return\no100 endwhile\no<autosub> endsub\n"
      "G21 G90 G17 G54 F200\nSHOW\nM70\no<imperialsub> call\nSHOW\nM72\nSHOW\no<autosub> call\nSHOW\n"
      "G1 X1\nM70\nG0 X2\nM72\nX3\nM2\n"));
  ASSERT_TRUE(l.result.ok) << l.first_error();
  const std::vector<std::string> want = {
      "0 1 200.0 170 1",  // main: G21 G90 F200 G17 G54
      "1 0 5.0 180 2",    // after the call: its G20 G91 F5 G18 G55 stay
      "0 1 200.0 170 1",  // M72: all restored
      "1 0 7.0 170 1",    // in the M73 subroutine
      "0 1 200.0 170 1",  // its return (from inside a loop) restored the caller's state
  };
  EXPECT_EQ(l.messages, want);
  ASSERT_EQ(l.moves.size(), 3u);
  EXPECT_EQ(l.moves[2].kind, MoveKind::kRapid) << "M72 leaves the motion mode (G0) as it is";
  EXPECT_DOUBLE_EQ(l.moves[2].end[0], 3.0);
}

// Each call level has its own saved state (a subroutine's M72 does not see the caller's M70),
// M71 forgets it (and stops M73's restore), and M72 without a saved state is an error at its
// column; so is a restore that would turn cutter compensation on or off.
TEST(GcodeModalState, LevelsInvalidationAndErrors) {
  Listing l = list_program("o<s> sub\nM72\no<s> endsub\nM70\no<s> call\nM2\n");
  EXPECT_NE(l.first_error().find("test.ngc:2:1: error: M72 with no modal state saved at this call level (this subroutine call); expected M70"), std::string::npos)
      << l.first_error();
  l = list_program("M70\nM71\nG20\nM72\nM2\n");
  EXPECT_NE(l.first_error().find("test.ngc:4:1: error: M72 with no modal state saved at this level (the main program)"), std::string::npos) << l.first_error();
  l = list_program(with_state("o<s> sub\nM73\nG20\nM71\no<s> endsub\nG21\no<s> call\nSHOW\nM2\n"));
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_EQ(l.messages, std::vector<std::string>{"1 1 0.0 170 1"}) << "M71 stopped the restore: G20 stays";
  l = list_program("G0 X0 Y0\nM70\nG41.1 D1 G1 X1 F100\nM72\nG40 G1 X2\nM2\n");
  EXPECT_NE(l.first_error().find("test.ngc:4:1: error: M72 would change cutter radius compensation (G41/G42 now, G40 when the state was saved)"), std::string::npos)
      << l.first_error();
  // M73 in the main program is accepted (it saves; LinuxCNC's M2 restores nothing)
  l = list_program(with_state("M73\nG20\nSHOW\nM2\n"));
  ASSERT_TRUE(l.result.ok) << l.first_error();
  EXPECT_EQ(l.messages, std::vector<std::string>{"1 1 0.0 170 1"});
}

// ---- messages and comments ----

TEST(GcodeMessages, MsgIsRawDebugIsSubstitutedInProgramOrder) {
  const Listing l = list_program(
      "#1=2\n#<d>=0.5\n(MSG, depth #1)\nG0 X1\n(DEBUG, depth #1 and #<d> %d#1 %.2f#<d> #<none>)\nG0 X2\n(print,not shown)\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.lines.size(), 4u);
  EXPECT_EQ(l.lines[0], "MSG  depth #1") << "MSG is not substituted (LinuxCNC)";
  EXPECT_EQ(l.lines[1].rfind("L4 rapid", 0), 0u);
  EXPECT_EQ(l.lines[2], "MSG  depth 2.000000 and 0.500000 2 0.50 ######");
  EXPECT_EQ(l.lines[3].rfind("L6 rapid", 0), 0u);
}

TEST(GcodeMessages, DebugSeesTheLinesOwnAssignment) {
  const Listing l = list_program("#1=1\n#1=7 (DEBUG,#1)\nM2\n");
  ASSERT_EQ(l.messages.size(), 1u);
  EXPECT_EQ(l.messages[0], "7.000000");
}

TEST(GcodeMessages, Parameter5599SwitchesDebugMessagesOffAndOn) {
  // LinuxCNC: #5599 = 0 hides (DEBUG,...), 1 (its value at start) shows them; MSG is not affected
  const Listing l = list_program("#2=#5599\n(DEBUG,a #2)\n#5599=0\n(DEBUG,b)\n(MSG,c)\n#5599=1\n(DEBUG,d)\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.messages.size(), 3u);
  EXPECT_EQ(l.messages[0], "a 1.000000");
  EXPECT_EQ(l.messages[1], "c");
  EXPECT_EQ(l.messages[2], "d");
  EXPECT_TRUE(list_program("#5598=1\nM2\n").has_error("read-only")) << "its neighbours stay read-only";
}

TEST(GcodeMessages, NestedCommentsAreAcceptedWithAWarningNamingTheColumn) {
  const Listing l = list_program("T1 M6 (HSS Twist Drill, 0.5mm (R))\nG0 X1\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  bool found = false;
  for (const Diagnostic& d : l.result.diagnostics) {
    if (d.message.find("nested '('") != std::string::npos) {
      found = true;
      EXPECT_EQ(d.line, 1);
      EXPECT_EQ(d.column, 31);
    }
  }
  EXPECT_TRUE(found);
}

TEST(GcodeListing, StopsAtTheFirstError) {
  const Listing l = list_program("G0 X1\nG0 X#<undefined>\nG0 X3\nM2\n");
  EXPECT_FALSE(l.result.ok);
  ASSERT_EQ(l.moves.size(), 1u) << "as LinuxCNC's interpreter, nothing after the first error";
  EXPECT_DOUBLE_EQ(l.moves[0].end[0], 1.0);
}

TEST(GcodeListing, PrintMovesFormat) {
  const Listing l = list_program("G0 X1 Y2 Z3\nG1 X-0.0000001 F60\nG4 P1\nM0\nM2\n");
  ASSERT_TRUE(l.result.ok) << l.first_error();
  ASSERT_EQ(l.lines.size(), 3u) << "pauses and the end are not moves";
  EXPECT_EQ(l.lines[0], "L1 rapid (0.000000,0.000000,0.000000)->(1.000000,2.000000,3.000000)");
  EXPECT_EQ(l.lines[1], "L2 line (1.000000,2.000000,3.000000)->(0.000000,2.000000,3.000000)");
  EXPECT_EQ(l.lines[2], "L3 dwell (0.000000,2.000000,3.000000)->(0.000000,2.000000,3.000000)");
}

}  // namespace
}  // namespace pcnc::test
