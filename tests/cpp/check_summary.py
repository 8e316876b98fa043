"""Runs one C++ test executable and checks its exit code and summary lines.

CTest calls it (tests/cpp/CMakeLists.txt):  check_summary.py <test name> <executable>
Exit code 0 when the executable passed and printed every expected line; otherwise the
executable's output and the first expectation that failed, and exit code 1.
"""
from __future__ import annotations

import re
import subprocess
import sys

RUN_TIMEOUT = 600  # seconds


class CheckFailed(Exception):
    """An expectation a C++ test's output or product did not meet."""


def require(condition: bool, what: str) -> None:
    if not condition:
        raise CheckFailed(what)


def lines(pattern: str, output: str) -> list:
    return re.findall(pattern, output, re.MULTILINE)


def check_no_allocation(output: str) -> None:
    # The counter proved it sees std::vector, aligned new and libc's malloc...
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    # ...and then saw nothing during 10^5 hybrid calls with flag changes, on a rigid tree, on the
    # same tree with flexible bodies, on that one with armatures, and on the rigid tree with
    # appendages of 8 and 4 modes.
    require(bool(lines(r"^tree with flexible bodies: \d+ bodies \([1-9]\d* flexible\)", output)),
            "a tree with flexible bodies")
    require(len(lines(r"^calls: 100000 hybrid_dynamics, \d+ other, \d+ flag changes; failed statuses: 0; energies from "
                      r"one sweep unequal to the separate calls: 0$", output)) == 4,
            "10^5 hybrid calls without a failed status, and mechanical_energy equal to the separate energies, on the "
            "four models")
    require(bool(lines(r"^flexible tree with armature: \d+ bodies \([1-9]\d* flexible\)", output)),
            "the model with armatures")
    require(bool(lines(r"^tree with appendages: \d+ bodies \(2 flexible\)", output)), "the model with appendages")
    require(len(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)) == 4,
            "zero allocations and frees, on the four models")
    require(bool(lines(r"^test_no_allocation: PASS: 100000 hybrid_dynamics calls per model$", output)),
            "the PASS line")


def check_float_vs_double(output: str) -> None:
    match = re.search(r"^test_float_vs_double: PASS: max relative error (\S+) rigid, (\S+) with flexible bodies, "
                      r"(\S+) on cassini \(tolerance 1e-04\), \d+ states per model, 0 failures$", output, re.MULTILINE)
    require(match is not None, "the PASS line with the three errors")
    require(max(float(match.group(k)) for k in (1, 2, 3)) <= 1e-4, "float within 1e-4 of double")


def check_loops_float_vs_double(output: str) -> None:
    """constrained_dynamics in float against double on random loop models of bounded condition number."""
    require(bool(lines(r"^cases: 48 accepted \([1-9]\d* with redundant loop equations, \d+ of them with indeterminate "
                       r"multipliers\), \d+ rejected; largest condition numbers", output)),
            "48 cases, some redundant, with their condition numbers")
    match = re.search(r"^test_loops_float_vs_double: PASS: max relative error (\S+) \(tolerance 1e-04\), "
                      r"48 cases, 0 failures$", output, re.MULTILINE)
    require(match is not None, "the PASS line")
    require(float(match.group(1)) <= 1e-4, "float within 1e-4 of double")


def check_sim_no_allocation(output: str) -> None:
    """10^5 steps of each built-in scene, RK4 and semi-implicit Euler, with events firing; and the HIL loop,
    paced and as fast as possible, with real-time scheduling requested, and over the UDP link under hostile
    traffic with the clamp, reject and stop policies."""
    rows = lines(r"^(\S+) \((rk4|euler)\): 100000 steps, 0 allocations, 0 frees, 0 failed statuses", output)
    require(len(rows) == 4, "10^5 allocation-free steps of both scenes with both integrators")
    hil = lines(r"^hil runner \((paced, 10000 Hz, floor after the run|as fast as possible, 10000 Hz, floor after the "
                r"run|paced, 2000 Hz, floor interleaved)\): (?:20000|4000) steps, 0 allocations, 0 frees, status ok;.*"
                r"snapshots read by another thread [1-9]\d*, inconsistent 0, last snapshot the final state; "
                r"floor periods (?:5000|0|1000)$", output)
    require(sorted(hil) == ["as fast as possible, 10000 Hz, floor after the run", "paced, 10000 Hz, floor after the run",
                            "paced, 2000 Hz, floor interleaved"],
            "the HIL runner, paced (the floor after the run and interleaved) and as fast as possible, its snapshots "
            "read by another thread")
    require(bool(lines(r"^state snapshot: 1000000 published, [1-9]\d* read by another thread, 0 torn, \d+ reads given up, "
                       r"0 allocations, 0 frees$", output)), "the snapshot's sequence lock: no torn read")
    udp = lines(r"^hil runner over UDP \((clamp|reject)\): 20000 steps, 0 allocations, 0 frees, status ok;", output)
    require(sorted(udp) == ["clamp", "reject"], "the HIL runner over UDP with the clamp and reject policies")
    require(bool(lines(r"^hil runner over UDP \(stop\): 0 allocations, 0 frees, stopped at step \d+ of 20000 by DOF 0$",
                       output)), "the HIL runner over UDP with the stop policy")
    require(bool(lines(r"^test_sim_no_allocation: PASS$", output)), "the PASS line")


def check_loops_no_allocation(output: str) -> None:
    """10^4 constrained_dynamics calls (and loop_residual, loop_rank) on each of five models: trees of 60 and 20
    bodies with a loop of every kind (the articulated-body response; the mass matrix in tree frames), the
    20-body tree with flexible bodies added (the mass matrix in body frames), the four-bar and the Delta robot
    (the mass matrix in tree frames)."""
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    require(bool(lines(r"^loop solvers: 60-body tree articulated, 20-body tree mass matrix, four-bar mass matrix, "
                       r"Delta robot mass matrix$", output)), "both loop solvers run")
    require(bool(lines(r"^60-body rigid tree: 60 bodies \(0 flexible\)$", output)), "the 60-body rigid tree")
    require(bool(lines(r"^20-body rigid tree: 20 bodies \(0 flexible\)$", output)), "the 20-body rigid tree")
    require(bool(lines(r"^20-body tree with flexible bodies: \d+ bodies \([1-9]\d* flexible\)$", output)),
            "the tree with flexible bodies")
    require(bool(lines(r"^four-bar: 3 bodies \(0 flexible\)$", output)), "the four-bar")
    require(bool(lines(r"^Delta robot: 10 bodies \(0 flexible\)$", output)), "the Delta robot")
    require(len(lines(r"^loops: 5, equations: 20, nv = \d+", output)) == 3, "five loops, 20 equations, on the trees")
    require(len(lines(r"^calls: 10000 constrained_dynamics; failed statuses: 0$", output)) == 5,
            "10^4 calls on each model, none failed")
    require(len(lines(r"^joint wrench calls: [1-9]\d*; rank-deficient Delassus with prescribed DOFs: [1-9]\d*; "
                      r"inconsistent loop equations \(least-squares answer\): \d+$", output)) == 5,
            "joint wrenches and the minimum-norm actuator forces exercised on each model")
    require(len(lines(r"^distance loop without length \((neutral|at q)\): ", output)) == 2,
            "distance loops measured at the neutral and at a given configuration")
    require(len(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)) == 5,
            "zero allocations on each model")
    require(bool(lines(r"^test_loops_no_allocation: PASS$", output)), "the PASS line")


def check_joint_angles(output: str) -> None:
    """The joint-angle table against std::sin and std::cos, in double and float, and non-finite angles."""
    chosen = lines(r"^model: 48 bodies, 40 table slots, kernel (polynomial AVX2|libmvec SSE2|std)$", output)
    require(len(chosen) == 1, "40 slots on the 48-body chain (36 revolute, 2 universal joints' two), and the kernel named")
    match = re.search(r"^double: (\d+) angles, max error (\S+) ulp; float: (\d+) angles, max error (\S+) ulp "
                      r"\(tolerance 4 ulp\)$", output, re.MULTILINE)
    require(match is not None, "the error line")
    require(int(match.group(1)) >= 2000 and int(match.group(3)) >= 1900, "about 2000 angles in each precision")
    require(max(float(match.group(2)), float(match.group(4))) <= 4.0, "within 4 ulp")
    kernels = lines(r"^kernels: (.*)$", output)
    require(len(kernels) == 1 and kernels[0].endswith("std (0.00 ulp)"), "every kernel compared, std last")
    require(kernels[0].startswith(chosen[0] + " ("), "the chosen kernel compared first")
    require(not chosen[0] == "polynomial AVX2" or "libmvec AVX2" in kernels[0] or "libmvec" not in kernels[0],
            "beside the polynomial, libmvec's AVX2 kernel compared wherever libmvec is")
    require(bool(lines(r"^non-finite angles: 120 of 120 double entries NaN, 120 of 120 float$", output)),
            "NaN for every non-finite angle")
    require(bool(lines(r"^threads: 8 threads from the process's first call, 1000 tables each, 0 differ$", output)),
            "eight threads' first calls: the same tables")
    require(bool(lines(r"^test_joint_angles: PASS$", output)), "the PASS line")


def chosen_kernel(output: str) -> str:
    """The kernels line of a kernel comparison: every kernel compared, the chosen one first and the
    baseline last. Returns the chosen one's name."""
    kernels = re.search(r"^kernels: (.*) \(chosen: (.*)\)$", output, re.MULTILINE)
    require(kernels is not None and kernels.group(1).split(", ")[0] == kernels.group(2)
            and kernels.group(1).endswith("baseline"), "every kernel compared, the chosen first, the baseline last")
    return kernels.group(2)


def check_mass_matrix_kernels(output: str) -> None:
    """Every mass-matrix kernel against the baseline and the body-frame algorithm; the placement shapes."""
    require(bool(lines(r"^quarter-turn arm: 6 of 8 placements applied as axis permutations$", output)),
            "the quarter-turn arm's six permutations")
    chosen = chosen_kernel(output)
    match = re.search(r"^max relative difference: (\S+) between kernels, (\S+) from the body-frame algorithm "
                      r"\(tolerance 1e-14\), kernels differ bit for bit: (yes|no)$", output, re.MULTILINE)
    require(match is not None, "the difference line")
    require(max(float(match.group(1)), float(match.group(2))) <= 1e-14, "within 1e-14 of M's largest entry")
    require((match.group(3) == "yes") == (chosen != "baseline"),
            "a kernel other than the baseline rounds differently somewhere (it is other code)")
    require(bool(lines(r"^threads: 8 threads from the process's first call, 200 mass matrices each, 0 differ$",
                       output)), "eight threads' first calls: the same M")
    require(bool(lines(r"^test_mass_matrix_kernels: PASS: 3 models, 20 states each$", output)), "the PASS line")


def check_appendage_kernels(output: str) -> None:
    """Every appendage kernel against the baseline and the full elimination, mode counts 1 to 7."""
    chosen = chosen_kernel(output)
    match = re.search(r"^max relative difference: (\S+) between kernels \(tolerance 1e-14\), (\S+) from the full "
                      r"elimination \(tolerance 1e-13\), kernels differ bit for bit: (yes|no)$", output, re.MULTILINE)
    require(match is not None, "the difference line")
    require(float(match.group(1)) <= 1e-14 and float(match.group(2)) <= 1e-13, "within the tolerances")
    require((match.group(3) == "yes") == (chosen != "baseline"),
            "a kernel other than the baseline rounds differently somewhere (it is other code)")
    require(bool(lines(r"^threads: 8 threads from the process's first call, 200 cassini dynamics each, 0 differ$",
                       output)), "eight threads' first calls: the same qdd")
    require(bool(lines(r"^test_appendage_kernels: PASS: mode counts 1 to 7, 20 states each$", output)), "the PASS line")


def check_loop_force_stiffness_no_allocation(output: str) -> None:
    """2000 calls on a 20-body tree with one loop of every kind, against central differences."""
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    require(bool(lines(r"^bodies: 20, nv = \d+, loops: 5 \(20 equations\)$", output)), "five loops, 20 equations")
    require(bool(lines(r"^calls: 2000; failed statuses: 0$", output)), "2000 calls without a failed status")
    match = re.search(r"^central differences: max relative error (\S+) \(tolerance 1e-08\)$", output, re.MULTILINE)
    require(match is not None and float(match.group(1)) <= 1e-8, "central differences within 1e-8")
    require(bool(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)), "zero allocations and frees")
    require(bool(lines(r"^test_loop_force_stiffness_no_allocation: PASS$", output)), "the PASS line")


def check_loop_sim_no_allocation(output: str) -> None:
    """10^4 steps of a five-bar and a four-bar with each integrator, locks and releases changing the loops'
    mobility, a drive taking over; then direct assembly and projection calls and named failures."""
    rows = lines(r"^(five-bar|four-bar) \((rk4|euler|dopri5)\): 10000 steps, 0 allocations, 0 frees, "
                 r"0 failed statuses, worst closure (\S+)$", output)
    require(len(rows) == 6, "10^4 allocation-free steps of both mechanisms with the three integrators")
    require(all(float(r[2]) <= 1e-12 for r in rows), "closure within 1e-12 after every step")
    require(bool(lines(r"^direct calls: 1000 of 1000 closed, 1000 of 1000 failures named loop 0, 0 allocations, "
                       r"0 frees$", output)), "allocation-free assembly, projection and named failures")
    require(bool(lines(r"^test_loop_sim_no_allocation: PASS$", output)), "the PASS line")


def check_frames_no_allocation(output: str) -> None:
    """2000 rounds of the frame functions (6 calls each) on a tree of every joint type with a welded frame."""
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    require(bool(lines(r"^calls: 12000 frame calls; finite results: yes; J v against frame_velocity: ", output)),
            "12000 calls with finite results")
    require(bool(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)), "zero allocations")
    require(bool(lines(r"^test_frames_no_allocation: PASS$", output)), "the PASS line")


def check_frames_float_vs_double(output: str) -> None:
    """Every frame output of every body of a 20-body tree at 16 states, and the centre-of-mass Jacobian."""
    match = re.search(r"^test_frames_float_vs_double: PASS: max relative error (\S+) \(tolerance 1e-04\), "
                      r"336 comparisons, 0 failures$", output, re.MULTILINE)
    require(match is not None, "the PASS line")
    require(float(match.group(1)) <= 1e-4, "float within 1e-4 of double")
def check_equation_terms_no_allocation(output: str) -> None:
    """10^4 calls of each equation term (and 100 christoffel_symbols) on a 20-body tree of every joint kind."""
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    require(bool(lines(r"^calls: 10000 of each term, 100 christoffel_symbols; failed statuses: 0$", output)),
            "10^4 calls without a failed status")
    match = re.search(r"^identities: 10000 states, max relative error (\S+) \(tolerance 1e-12\)$", output, re.MULTILINE)
    require(match is not None and float(match.group(1)) <= 1e-12, "the identities within 1e-12")
    require(bool(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)), "zero allocations and frees")
    require(bool(lines(r"^test_equation_terms_no_allocation: PASS$", output)), "the PASS line")


def check_derivatives_no_allocation(output: str) -> None:
    """2000 calls of each derivative function on a 20-body tree of every joint kind, two masks."""
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    require(bool(lines(r"^calls: 2000 of each; failed statuses or checks: 0$", output)),
            "2000 calls without a failed status or check")
    match = re.search(r"^identities: max relative error (\S+) \(tolerance 1e-11\)$", output, re.MULTILINE)
    require(match is not None and float(match.group(1)) <= 1e-11, "the identities within 1e-11")
    require(bool(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)), "zero allocations and frees")
    require(bool(lines(r"^test_derivatives_no_allocation: PASS$", output)), "the PASS line")


def check_force_elements_no_allocation(output: str) -> None:
    """10^4 calls of each dynamics entry point and 10^4 Simulator steps on a 20-body tree with springs."""
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    require(bool(lines(r"^force elements: [1-9]\d* joint springs, [1-9]\d* point springs$", output)),
            "joint and point springs")
    require(bool(lines(r"^calls: 10000 of each; failed statuses: 0$", output)), "10^4 calls without a failed status")
    match = re.search(r"^identities: max relative error (\S+) \(tolerance 1e-09\)$", output, re.MULTILINE)
    require(match is not None and float(match.group(1)) <= 1e-9, "the identities within 1e-9")
    require(bool(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)), "zero allocations and frees")
    require(bool(lines(r"^simulator: 10000 rk4 steps, 0 allocations, 0 frees, 0 failed statuses$", output)),
            "10^4 allocation-free Simulator steps")
    require(bool(lines(r"^test_force_elements_no_allocation: PASS$", output)), "the PASS line")


def check_parameters_no_allocation(output: str) -> None:
    """ParameterTable::set/get on every parameter of a 20-body tree, 2000 rounds, zero allocations."""
    require(bool(lines(r"^self-check: std::vector -> [1-9]\d* new", output)), "the allocation counter's self-check")
    require(bool(lines(r"^bodies: 20, parameters: [1-9]\d*$", output)), "a 20-body tree with parameters")
    require(bool(lines(r"^rounds: 2000, sets: [1-9]\d*; failed checks: 0; restored qdd error", output)),
            "2000 rounds without a failed check")
    require(bool(lines(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output)), "zero allocations")
    require(bool(lines(r"^test_parameters_no_allocation: PASS$", output)), "the PASS line")


def check_model_file(output: str) -> None:
    """Save/load/save of 14 models (scenes, random trees with flexible bodies, masks, springs) and hostile texts."""
    require(bool(lines(r"^round trips: 14 models, text and dynamics identical$", output)), "14 round trips")
    require(bool(lines(r"^hostile texts refused with a named item: 15$", output)), "15 hostile texts refused")
    require(bool(lines(r"^test_model_file: PASS$", output)), "the PASS line")


def check_batch(output: str) -> None:
    """Batched calls and rollouts against single calls and one Simulator per run; the pool's exceptions and hand-offs."""
    require(bool(lines(r"^batched calls: 3 models x 3 thread counts x lanes 1 and 4 x 64 rows, rows differing from "
                       r"the single calls: 0$", output)), "every batched row equal to its single call, packets too")
    require(bool(lines(r"^packet appendage update without lane models: the packet splits; with them: it stands: yes$",
                       output)), "the packet appendage update runs only with its lane models")
    require(bool(lines(r"^batched calls after a mass and a prescribed flag changed, 3 models x 2 thread counts x lanes 1 "
                       r"and 4 x 40 "
                       r"rounds of the five calls: allocations 0 \(counter works: yes\), rounds whose row 0 differs "
                       r"from the single call: 0$", output)), "batched calls without allocation, following the model")
    require(bool(lines(r"^rollouts: 2 thread counts x 6 runs, runs differing from one Simulator each: 0; "
                       r"failures reported as expected: 6 of 6$", output)), "rollouts equal, failures reported")
    require(bool(lines(r"^thread pool: exception rethrown and pool reused: yes; loops of 1200 that missed or repeated "
                       r"an index: 0$", output)), "the pool's exceptions and hand-offs")
    require(bool(lines(r"^test_batch: PASS$", output)), "the PASS line")


def check_packet_parameters(output: str) -> None:
    """Four runs with their own parameters in one Simulator of packets, against each run alone."""
    require(bool(lines(r"^packet model of four parameter sets: built, lane values differing from their model's: 0$",
                       output)), "the packet model holds each run's values in its lane")
    require(bool(lines(r"^four runs side by side, 200 RK4 steps: entries differing from each run alone: 0$", output)),
            "the four runs equal their Simulators bit for bit")
    require(bool(lines(r"^the same with two DOFs driven by sources \(cycloidal, spline\): entries differing: 0$",
                       output)), "the four runs with shared sources equal their Simulators")
    require(bool(lines(r"^the same with DOPRI5, each lane its own sub-steps: entries differing: 0; steps whose runs "
                       r"alone take different numbers of sub-steps: [1-9][0-9]*$", output)),
            "the four runs with DOPRI5 equal their Simulators, their sub-steps differing")
    require(bool(lines(r"^the same with a lock and a release at each run's times, due in the same steps: "
                       r"entries differing: 0$", output)), "the four runs with their events equal their Simulators")
    require(bool(lines(r"^events due in different steps: the packet splits$", output)),
            "events due in different steps split the packet")
    require(bool(lines(r"^an event time that is not finite in one lane: the packet is refused$", output)),
            "an event time that is not finite refuses the packet")
    require(bool(lines(r"^models that cannot share packets \(a placement's axes, an inertia's symmetry, a flag\): "
                       r"refused 3 of 3$", output)), "models with different derived properties or flags refused")
    require(bool(lines(r"^test_packet_parameters: PASS$", output)), "the PASS line")


def check_small_solves(output: str) -> None:
    """The free root's solve and the two-DOF hinge step against LLT and cholesky_in_place."""
    require(bool(lines(r"^spd_factor6: 2000 random P \(condition up to 1e6\), solve's max relative error / condition \S+$",
                       output)), "2000 free-root solves")
    require(bool(lines(r"^spd_factor6: singular pivot named as by cholesky_in_place: 6 of 6$", output)),
            "every singular pivot named")
    require(bool(lines(r"^two-DOF hinge: 2000 random D, max relative error of G \S+, factors within 2 ulp of "
                       r"cholesky_in_place's: 2000$", output)), "2000 two-DOF steps with the factor of cholesky_in_place")
    require(bool(lines(r"^two-DOF hinge: nearly singular D named pivot (1|-1), factor finite: yes$", output)),
            "the nearly singular D")
    require(bool(lines(r"^PASS: 0 failures$", output)), "no failure")


def check_packet_lanes(build: str, output: str) -> None:
    """Packet4d's operations against the double ones, bit for bit, in the given build."""
    match = re.search(rf"^{build} build: (\d+) lanes of arithmetic and (\d+) lanes of functions against the double "
                      r"operations$", output, re.MULTILINE)
    require(match is not None and min(int(match.group(1)), int(match.group(2))) > 100000,
            f"over 10^5 lanes of arithmetic and of functions compared ({build} build)")
    require(bool(lines(rf"^test_packet_lanes: PASS: {build} build, every lane bit for bit$", output)), "the PASS line")


def check_c_api(output: str) -> None:
    """The C API from a C program: every check line ok, and the PASS line."""
    require(len(lines(r"^ok: ", output)) >= 20 and not lines(r"^FAILED: ", output), "every check of the C program")
    require(bool(lines(r"^test_c_api: PASS: 0 checks failed$", output)), "the PASS line")


def check_c_api_no_allocation(output: str) -> None:
    """10^4 steps of cassini through the C API with inputs, mode switches, reads and saved states."""
    require(bool(lines(r"^c api \(cassini\): 10000 steps, 0 allocations, 0 frees, 0 failed calls$", output)),
            "10^4 allocation-free steps through the C API")
    require(bool(lines(r"^test_c_api_no_allocation: PASS$", output)), "the PASS line")


def check_fmu_no_allocation(output: str) -> None:
    """10^4 DoSteps of the FMU binary on cassini with inputs, mode switches, every output and saved states."""
    require(bool(lines(r"^fmu \(cassini, frame scan_el\): 10000 DoSteps, [1-9]\d* outputs read each, 0 allocations, "
                       r"0 frees, 0 failed calls$", output)), "10^4 allocation-free DoSteps")
    require(bool(lines(r"^a new FMU state inside the binary: [1-9]\d* allocations seen$", output)),
            "the counter seeing the binary's own allocations")
    require(bool(lines(r"^test_fmu_no_allocation: PASS$", output)), "the PASS line")


CHECKS = {
    "test_no_allocation": check_no_allocation,
    "test_float_vs_double": check_float_vs_double,
    "test_loops_float_vs_double": check_loops_float_vs_double,
    "test_sim_no_allocation": check_sim_no_allocation,
    "test_loops_no_allocation": check_loops_no_allocation,
    "test_loop_force_stiffness_no_allocation": check_loop_force_stiffness_no_allocation,
    "test_loop_sim_no_allocation": check_loop_sim_no_allocation,
    "test_frames_no_allocation": check_frames_no_allocation,
    "test_frames_float_vs_double": check_frames_float_vs_double,
    "test_equation_terms_no_allocation": check_equation_terms_no_allocation,
    "test_derivatives_no_allocation": check_derivatives_no_allocation,
    "test_force_elements_no_allocation": check_force_elements_no_allocation,
    "test_parameters_no_allocation": check_parameters_no_allocation,
    "test_model_file": check_model_file,
    "test_joint_angles": check_joint_angles,
    "test_mass_matrix_kernels": check_mass_matrix_kernels,
    "test_appendage_kernels": check_appendage_kernels,
    "test_packet_lanes": lambda output: check_packet_lanes("baseline", output),
    "test_packet_lanes_avx2": lambda output: check_packet_lanes("AVX2", output),
    "test_small_solves": check_small_solves,
    "test_batch": check_batch,
    "test_packet_parameters": check_packet_parameters,
    "test_c_api": check_c_api,
    "test_c_api_no_allocation": check_c_api_no_allocation,
    "test_fmu_no_allocation": check_fmu_no_allocation,
}


def main(argv: list) -> int:
    if len(argv) != 3 or argv[1] not in CHECKS:
        print(f"usage: {argv[0]} {{{','.join(CHECKS)}}} <executable>", file=sys.stderr)
        return 2
    name, executable = argv[1], argv[2]
    result = subprocess.run([executable], capture_output=True, text=True, timeout=RUN_TIMEOUT)
    output = result.stdout + result.stderr
    print(output, end="")
    if result.returncode != 0:
        print(f"{name} exited with {result.returncode}", file=sys.stderr)
        return 1
    try:
        CHECKS[name](output)
    except CheckFailed as missing:
        print(f"{name}: the output lacks {missing}", file=sys.stderr)
        return 1
    print(f"{name}: exit code 0 and every summary line as expected")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
