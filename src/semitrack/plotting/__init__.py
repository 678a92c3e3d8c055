"""The book's figures, drawn from the package's results in one house style, by subject.

Every ``*_figure`` function takes results computed by the package (arrays, tables, the results of
a study), draws one :class:`matplotlib.figure.Figure` (attached to no pyplot backend, so that a
notebook displays it, a script or the command line saves it) and returns ``(fig, axes)``; the
notebooks call them and compute nothing by hand. Nothing here selects a backend or changes the
global rcParams (:func:`apply_house_style` does, when a notebook asks for it).

Modules: :mod:`~.style` (line styles, figures, axes, legends), :mod:`~.receptance`,
:mod:`~.schematic` (the equivalent systems to scale), :mod:`~.truncation` (truncated FE tracks),
:mod:`~.boundary` (the broadband boundary), :mod:`~.contact` (the wheel on the rail), :mod:`~.imperfect`
(wheels over a dipped weld, forces in the track), :mod:`~.moving` (moving Green's functions beside the
truncated model), :mod:`~.window` (the travelling window beside the model that holds the path), :mod:`~.flats`
(wheel flats: the centre's path, impacts against speed, the contact filter), :mod:`~.studies` (a study's
table: percentiles with their intervals, exceedance, a scatter).
"""

from .boundary import (  # noqa: F401
    BOUNDARY_STYLE,
    band_error_figure,
    boundary_pulse_figure,
    boundary_receptance_figure,
    boundary_w1_figure,
    order_error_figure,
    passivity_margin_figure,
)
from .contact import (  # noqa: F401
    POSITION_STYLE,
    band_level_figure,
    force_history_figure,
    linear_force_figure,
    rolling_figure,
    run_figure,
)
from .decay import decay_rate_figure, local_change_figure  # noqa: F401
from .flats import centre_path_figure, contact_filter_figure, impact_speed_figure  # noqa: F401
from .imperfect import gap_figure, track_force_figure, weld_force_figure  # noqa: F401
from .moving import moving_force_figure  # noqa: F401
from .receptance import (  # noqa: F401
    central_response_figure,
    convergence_figure,
    fields_figure,
    phase_figure,
    receptance_figure,
)
from .schematic import (  # noqa: F401
    MASSLESS_FRACTION,
    PARAMETER_TEX,
    equivalent_schematic,
)
from .studies import exceedance_figure, percentile_figure, scatter_figure  # noqa: F401
from .style import (  # noqa: F401
    CENTRAL_LABELS,
    ELEMENT_COLOR,
    METHOD_STYLE,
    RC,
    apply_house_style,
    house_figure,
    house_style,
    legend_below,
    magnitude_axes,
    magnitude_label,
    mark_frequencies,
    new_figure,
    panels,
    phase_label,
    plot_magnitude,
    plot_phase,
    shade_above,
    show_lowest_tick_labels,
)
from .truncation import (  # noqa: F401
    long_track_error_figure,
    pulse_figure,
    pulse_panels,
    truncated_w1_figure,
    truncation_figure,
    w1_panels,
)
from .window import long_run_figure, window_force_figure  # noqa: F401
