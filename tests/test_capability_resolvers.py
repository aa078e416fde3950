"""The workspace, design-metric and asset capabilities: each resolver returns the family's
implementation or the default behind the same ABC, and no family keeps the old hooks."""

from __future__ import annotations

import pytest

from rcm_pin.analysis.workspace import NumericWorkspace, WorkspaceModel, workspace_model
from rcm_pin.catalog import table
from rcm_pin.design.metrics import NoMetrics, metric_source
from rcm_pin.interfaces.design import MetricSource
from rcm_pin.interfaces.viz import Assets
from rcm_pin.model.family import Family
from rcm_pin.viz.assets import NoAssets, assets

HOOKS = ("workspace_summary", "plot_workspace", "workspace_options", "design_metrics", "mesh_dirs")
FAMILIES = list({id(e.family): e.family for e in table.ENTRIES}.values())


class _Mech:
    """Just enough of a Mechanism for the resolvers (they read ``family``)."""

    def __init__(self, family: Family) -> None:
        self.family = family


def test_a_family_without_implementations_gets_the_defaults():
    mech = _Mech(Family())
    assert type(workspace_model(mech)) is NumericWorkspace
    assert workspace_model(mech).options == ("samples",)
    assert type(metric_source(Family())) is NoMetrics and metric_source(Family()).metrics() == {}
    assert type(assets(mech)) is NoAssets and assets(mech).mesh_dirs(mech) == ()


@pytest.mark.parametrize("family", FAMILIES, ids=lambda f: f.name)
def test_each_family_resolves_behind_the_abcs_and_has_no_old_hooks(family):
    mech = _Mech(family)
    assert isinstance(workspace_model(mech), WorkspaceModel)
    assert isinstance(metric_source(family), MetricSource)
    assert isinstance(assets(mech), Assets)
    assert not [h for h in HOOKS if hasattr(family, h)]


def test_the_families_metrics_and_assets():
    by_name = {f.name: f for f in FAMILIES}
    for name in ("rcm", "planar_3rrr", "spherical_3rrr", "four_bar"):
        metrics = metric_source(by_name[name]).metrics()
        assert metrics and all(m.name == k for k, m in metrics.items())
    assert type(assets(_Mech(by_name["rcm"]))) is NoAssets
    assert type(assets(_Mech(by_name["arm"]))) is not NoAssets
