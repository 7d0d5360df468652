"""A terrain's settings (mjrft.settings): each from its argument, else the model's mjrft:* entry, else the default,
checked; a misspelled key is named with the valid ones."""

from __future__ import annotations

import mujoco
import pytest

import mjrft
from mjrft.settings import DEFAULTS, custom_entries, resolve_settings

FOOT = """<mujoco>{custom}<worldbody><body name="foot"><freejoint/><geom name="sole" type="box" size=".02 .02 .02"/>
</body></worldbody></mujoco>"""
CUSTOM = ('<custom><text name="mjrft:medium" data="glass3_cp"/><numeric name="mjrft:resolution" data="0.02"/>'
          '</custom>')


def test_an_argument_wins_over_the_models_entry_which_wins_over_the_default():
    plain = mujoco.MjModel.from_xml_string(FOOT.format(custom=""))
    carried = mujoco.MjModel.from_xml_string(FOOT.format(custom=CUSTOM))
    assert custom_entries(plain) == {} and custom_entries(carried) == {"medium": "glass3_cp", "resolution": 0.02}
    default = resolve_settings(plain, resolution=0.01)
    assert (default.medium.name, default.law, default.surface) == (DEFAULTS["medium"], DEFAULTS["law"], 0.0)
    from_model = resolve_settings(carried)
    assert (from_model.medium.name, from_model.resolution, from_model.resolution_auto) == ("glass3_cp", 0.02, False)
    given = resolve_settings(carried, medium="poppy_lp", resolution=0.03)
    assert (given.medium.name, given.resolution) == ("poppy_lp", 0.03)
    with pytest.raises(ValueError, match="yield_displacement must be finite and >= 0"):
        resolve_settings(carried, yield_displacement=-1.0)


def test_misspelled_custom_key_warns_naming_the_key_and_the_valid_ones():
    from mjrft.models import model_path

    xml = open(model_path("hexapod")).read().replace('name="mjrft:medium"', 'name="mjrft:meduim"')
    m = mujoco.MjModel.from_xml_string(xml)
    with pytest.warns(UserWarning, match=r"'mjrft:meduim' is not an mjrft setting and is ignored; did you mean "
                                         r"'mjrft:medium'\? valid keys: mjrft:medium, mjrft:law"):
        t = mjrft.GranularTerrain(m, resolution=0.02)
    assert t.medium.name == "poppy_cp"  # the default, as the misspelled key is ignored
