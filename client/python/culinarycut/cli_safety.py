"""`culinarycut safety`: the manipulation safety module's force model. `dataset` sweeps knife speed and
material through the MPM engine (cc-cut), `fit` fits the posynomial force model the server's limiter reads,
`predict` prints its force and the safe speed under a force limit."""
from __future__ import annotations

import os
import sys
from pathlib import Path

EXIT_USAGE = 2
EXIT_FAILED = 1
EXIT_INTERRUPTED = 130
# Where the server reads the force model from (culinarycut.safety.asset.default_model_path).
MODEL_LOCATION = "$CULINARYCUT_ASSETS_DIR/safety/force_model.json, else assets/safety/force_model.json in the checkout"


def _numbers(option: str):
    """An argparse type: a number, or several separated by commas."""
    def parse(text: str) -> list[float]:
        try:
            return [float(item) for item in text.split(",") if item.strip()]
        except ValueError:
            raise ValueError(f"{option}: {text!r} is not a number or a comma list of numbers") from None
    parse.__name__ = option
    return parse


def _flat(values) -> tuple:
    return tuple(v for group in values for v in (group if isinstance(group, list) else [group]))


def cmd_dataset(args) -> int:
    from culinarycut.safety.binary import cc_cut_binary, engine_qualities
    from culinarycut.safety.dataset import DatasetMismatch, run_sweep
    from culinarycut.safety.sweep import Sweep, validate
    defaults = Sweep()
    sweep = Sweep(speeds_m_s=_flat(args.speeds) if args.speeds else defaults.speeds_m_s,
                  foods=tuple(f.strip() for group in args.foods for f in group.split(",") if f.strip())
                  if args.foods else defaults.foods,
                  scales=_flat(args.scales) if args.scales else defaults.scales,
                  youngs_modulus_mpa=_flat(args.youngs_mpa) if args.youngs_mpa else defaults.youngs_modulus_mpa,
                  yield_stress_kpa=_flat(args.yield_kpa) if args.yield_kpa else defaults.yield_stress_kpa,
                  fracture_toughness_j_m2=_flat(args.toughness) if args.toughness else defaults.fracture_toughness_j_m2,
                  quality=args.quality)
    if args.workers < 1:
        raise ValueError(f"--workers: must be at least 1, got {args.workers}")
    cc_cut = Path(args.cc_cut) if args.cc_cut else cc_cut_binary()
    if not (cc_cut.is_file() and os.access(cc_cut, os.X_OK)):
        raise ValueError(f"--cc-cut: no executable cc-cut at {cc_cut}; build it (scripts/build.sh), pass --cc-cut "
                         "or set CULINARYCUT_CC_CUT")
    validate(sweep, engine_qualities(cc_cut))
    try:
        result = run_sweep(sweep, Path(args.out), cc_cut, workers=args.workers, progress=not args.no_progress)
    except DatasetMismatch as err:
        raise ValueError(str(err)) from None
    rate = result.ran / result.wall_s * 3600 if result.ran and result.wall_s > 0 else 0.0
    print(f"{args.out}: {result.already_done + result.ran} of {result.total} samples recorded; this run: "
          f"{result.ran} in {result.wall_s:.1f} s ({rate:.0f} samples/h on {args.workers} workers)"
          + (f", {result.failed} failed" if result.failed else ""))
    return EXIT_FAILED if result.failed else 0


def cmd_fit(args) -> int:
    from culinarycut.safety.asset import default_model_path, write_asset
    from culinarycut.safety.dataset import HEADER_FILE, DatasetMismatch
    from culinarycut.safety.model_io import asset_from_fit, fit_dataset
    directory = Path(args.dataset)
    if not (directory / HEADER_FILE).is_file():
        raise ValueError(f"DATASET: {directory} holds no {HEADER_FILE}; make one with `culinarycut safety dataset`")
    if not 0 < args.held_out < 1:
        raise ValueError(f"--held-out: must be in (0, 1), got {args.held_out}")
    try:
        result, x, rows, header = fit_dataset(directory, seed=args.seed, held_out_fraction=args.held_out)
    except DatasetMismatch as err:
        raise ValueError(f"DATASET: {err}") from None
    out = Path(args.out) if args.out else default_model_path()
    asset = asset_from_fit(result, x, header, directory, out)
    for name, rmse in result.cross_validation.items():
        print(f"  {name:<28} {len(_family(name)):2d} monomials, cross-validated RMSE {rmse:.3f} N"
              + ("  <- chosen" if name == result.family else ""))
    held = result.held_out
    print(f"held out {result.held_out_count} of {result.samples}: R^2 {held['r2']:.4f}, RMSE {held['rmse_n']:.3f} N, "
          f"max |error| {held['max_abs_error_n']:.3f} N; monotonic in speed on a grid: {result.monotonic_in_speed}")
    for term in asset["terms"]:
        print(f"  {term['coefficient']:12.6g} * {_monomial(term['exponents'])}")
    if not result.monotonic_in_speed:
        print("error: the fitted model falls with speed somewhere on the grid; not written", file=sys.stderr)
        return EXIT_FAILED
    write_asset(asset, out)
    print(f"wrote {out}")
    if args.plots:
        from culinarycut.safety.model_io import inputs_and_forces
        from culinarycut.safety.plots import plot_fit
        for path in plot_fit(result, x, inputs_and_forces(rows)[1], rows, Path(args.plots)):
            print(f"wrote {path}")
    return 0


def _family(name: str) -> list:
    from culinarycut.safety.fit import FAMILIES
    return FAMILIES[name]


def _monomial(exponents: list[float]) -> str:
    from culinarycut.safety.posynomial import INPUTS
    parts = [name if a == 1 else f"{name}^{a:g}" for name, a in zip(INPUTS, exponents) if a != 0]
    return " * ".join(parts) or "1"


def cmd_predict(args) -> int:
    from culinarycut.safety.asset import AssetError, ForceModel, default_model_path
    from culinarycut.safety.speed_limit import material_inputs, safe_speed
    path = Path(args.model) if args.model else default_model_path()
    if not path.is_file():
        given = "" if args.model else " (the server's: set CULINARYCUT_ASSETS_DIR to the folder holding safety/)"
        raise ValueError(f"--model: no force model at {path}{given}; pass --model FILE, or fit one with "
                         "`culinarycut safety fit`")
    try:
        model = ForceModel.load(path)
    except (OSError, AssetError) as err:
        raise ValueError(f"--model: {err}") from None
    for option, value in (("--speed", args.speed), ("--youngs-mpa", args.youngs_mpa), ("--yield-kpa", args.yield_kpa),
                          ("--toughness", args.toughness), ("--edge-length-m", args.edge_length_m),
                          ("--f-max", args.f_max)):
        if not value >= 0 or value == float("inf"):
            raise ValueError(f"{option}: must be a finite number >= 0, got {value}")
    x = material_inputs(args.speed, args.youngs_mpa, args.yield_kpa, args.toughness, args.edge_length_m)
    force_n, outside = model.predict(x)
    limit = safe_speed(model, x, args.f_max)
    flag = f" (out of range: x{model.out_of_range_factor:g})"
    print(f"F_hat at {args.speed:g} m/s: {force_n:.3f} N" + (flag if outside else ""))
    print(f"v_safe for F_max {args.f_max:g} N: {limit.v_safe_m_s:.4f} m/s (F_hat there {limit.predicted_force_n:.3f} N)"
          + (flag if limit.out_of_range else ""))
    return 0


def register(sub) -> None:
    safety = sub.add_parser("safety", help="the safety module's force model: dataset, fit, predict")
    safety.set_defaults(func=run_command, timeout=30.0)
    commands = safety.add_subparsers(dest="safety_command", required=True, metavar="{dataset,fit,predict}")

    ds = commands.add_parser("dataset", help="sweep knife speed and material through cc-cut (resumable)")
    ds.add_argument("--out", required=True, help="dataset folder; rerunning with the same folder adds what is missing")
    ds.add_argument("--speeds", type=_numbers("--speeds"), nargs="+", metavar="M_S",
                    help="knife descent speeds, m/s (default: 5 log-spaced from 0.02 to 4)")
    ds.add_argument("--foods", nargs="+", metavar="FOOD", help="foods (default: cucumber apple)")
    ds.add_argument("--scales", type=_numbers("--scales"), nargs="+", help="food scales (default: 0.4 0.8)")
    ds.add_argument("--youngs-mpa", type=_numbers("--youngs-mpa"), nargs="+", metavar="MPA",
                    help="Young's moduli, MPa (default: 0.1 1 5)")
    ds.add_argument("--yield-kpa", type=_numbers("--yield-kpa"), nargs="+", metavar="KPA",
                    help="yield stresses, kPa (default: 20 350)")
    ds.add_argument("--toughness", type=_numbers("--toughness"), nargs="+", metavar="J_M2",
                    help="fracture toughnesses, J/m^2 (default: 50 250)")
    ds.add_argument("--quality", default="draft", help="MPM preset: draft, standard or fine (default %(default)s)")
    ds.add_argument("--workers", type=int, default=2, help="cc-cut processes at a time, one thread each")
    ds.add_argument("--cc-cut", help="the cc-cut binary (default: $CULINARYCUT_CC_CUT or build/tools/cc_cut/cc-cut)")
    ds.add_argument("--no-progress", action="store_true", help="no progress bar")
    ds.set_defaults(safety_func=cmd_dataset)

    fit = commands.add_parser("fit", help="fit the posynomial force model to a dataset and write the asset")
    fit.add_argument("dataset", metavar="DATASET", help="a folder made by `culinarycut safety dataset`")
    fit.add_argument("--out", help=f"the asset (default: the one the server reads, {MODEL_LOCATION})")
    fit.add_argument("--held-out", type=float, default=0.2, help="fraction of samples held out (default %(default)s)")
    fit.add_argument("--seed", type=int, default=0, help="seed of the held-out split and the folds")
    fit.add_argument("--plots", metavar="DIR", help="also draw predicted vs measured and force vs speed (PNG) there")
    fit.set_defaults(safety_func=cmd_fit)

    pred = commands.add_parser("predict", help="the model's peak force at a speed and the safe speed under F_max")
    pred.add_argument("--model", help=f"the asset (default: the one the server reads, {MODEL_LOCATION})")
    pred.add_argument("--speed", type=float, required=True, help="knife speed, m/s")
    pred.add_argument("--youngs-mpa", type=float, required=True, help="Young's modulus, MPa")
    pred.add_argument("--yield-kpa", type=float, required=True, help="yield stress, kPa")
    pred.add_argument("--toughness", type=float, required=True, help="fracture toughness, J/m^2")
    pred.add_argument("--edge-length-m", type=float, required=True, help="the food's extent along the blade, m")
    pred.add_argument("--f-max", type=float, default=100.0, help="force limit, N (default %(default)s: the paper's)")
    pred.set_defaults(safety_func=cmd_predict)


def run_command(args) -> int:
    try:
        return args.safety_func(args)
    except ValueError as err:
        print(f"error: {err}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print("\nstopped; run the same command again to resume", file=sys.stderr)
        return EXIT_INTERRUPTED


__all__ = ["register", "run_command"]
