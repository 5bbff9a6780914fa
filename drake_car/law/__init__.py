"""The laws (friction, tyres, road, comfort, numerics): pure functions and their parameters.
Before any of them imports numba, its on-disk cache is pointed at a writable folder where the
package's own is not (``law.numerics.cache_folder``)."""

from drake_car.law.numerics.cache_folder import use_for_numba

use_for_numba()
