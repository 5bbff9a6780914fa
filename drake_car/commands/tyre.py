"""A tyre property file's steady-state curves, figures and summary:

  DIR/curves.csv     fz_N, kappa, alpha_rad, gamma_rad, fx_N, fy_N, mz_Nm (and the case):
                     pure-slip sweeps at 0.5, 1, 1.5 and 2 FNOMIN (inside the file's FZMIN..FZMAX),
                     with and without camber (3 deg), and combined slip (kappa swept at
                     alpha = 2, 5, 8 deg); ISO-W signs, steady state, speed LONGVL
  DIR/*.png          Fy-alpha, Mz-alpha, Fx-kappa at those loads, the friction ellipse at
                     FNOMIN, slip and cornering stiffness against load
  DIR/summary.txt    format and version read, peak mu, stiffnesses at FNOMIN, the
                     coefficients that took defaults, the plausibility check's warnings

The file is read as its format defines it (PAC2002, MF 6.1, MF 6.2 or drake_car's own
MF_2006_BOOK); MF 6.x at its INFLPRES unless --pressure_Pa. Bad input (an unreadable or
unsupported file, a folder): one line on stderr naming it, exit status 2, nothing written.

  drake-car-tyre --tir tests/data/tyres/Sedan_Pac02Tire.tir --out results/tyre_sedan
"""

import sys

from drake_car.commands import cli
from drake_car.law.tyre.magic_formula import MagicFormulaTyre
from drake_car.model.loading import tir_path
from drake_car.results.folder import output_folder
from drake_car.study.handling import tyre_curves


def main(argv=None):
    p = cli.parser(__doc__, name="tyre")
    p.add_argument("--tir", required=True,
                   help="tyre property file: a path, or a name in the package's urdf/ data")
    p.add_argument("--pressure_Pa", type=cli.positive("pressure_Pa"), default=None,
                   help="inflation pressure (MF 6.x files; default the file's INFLPRES)")
    args = p.parse_args(argv)
    tyre = MagicFormulaTyre.from_file(tir_path(args.tir, "--tir"), pressure_Pa=args.pressure_Pa)
    with output_folder(args.out) as out:
        text, _ = tyre_curves.write(tyre, out)
    print(text + f"wrote {args.out}", file=sys.stderr)


def console():
    """The console script ``drake-car-tyre``."""
    cli.run_main(main)


if __name__ == "__main__":
    console()
