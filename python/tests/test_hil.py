"""`deploywatch.hil`, the twin of `deploywatch hil`: a bundled run sent in
real time to the serial-link firmware under QEMU, every sample delivered
on a clean link, every status back and bit-identical with the host core's
(the command's own check), the samples echoed as sent. It needs the firmware ELF that
`scripts/firmware.sh build` makes: `scripts/firmware.sh test` runs this
file after building it, and `scripts/test.sh` after both its lanes (one
builds the firmware, the other the package); without the ELF the QEMU test
is skipped and says why. The refusals need no firmware.

    bash scripts/firmware.sh build && .venv/bin/pytest python/tests/test_hil.py -q
"""

import os

import numpy as np
import pytest

import deploywatch as dw
from deploywatch import InputError

T01 = "data/mechanisms/seed001_T01.toml"
RUN = "data/examples/a_seed001_eft/seed001_T01.csv"


def _elf(root):
    """`DW_HIL_ELF` (what scripts/firmware.sh passes), else where
    `scripts/firmware.sh build` puts it by default."""
    default = root / "firmware-example" / "target" / "thumbv7em-none-eabihf" / "release"
    return os.environ.get("DW_HIL_ELF", str(default / "deploywatch-firmware-uart"))


def test_hil_under_qemu_gives_replays_statuses(root, monkeypatch):
    monkeypatch.chdir(root)
    elf = _elf(root)
    if not os.path.exists(elf):
        pytest.skip(f"no serial-link firmware at {elf}: scripts/firmware.sh test builds it and runs this test")
    mech = dw.Mechanism.from_toml(T01)
    got = dw.hil(RUN, mech, elf=elf, duration=1.0)
    want = dw.replay(RUN, mech)
    n = len(got.statuses.columns["t_s"])
    assert n > 0
    fates = got.latency.states["fate"]
    assert len(fates) == n and set(fates) == {"sent"}, set(fates)
    # The call returns only when every status is bit-identical with the
    # host core's on the samples the firmware got (the CLI's own check;
    # DeploywatchError otherwise). The samples themselves come back as sent:
    # the time stamps and the angles of `replay`'s first rows.
    for col in ["t_s"] + [f"phi{j}_deg" for j in (1, 2, 3)]:
        np.testing.assert_array_equal(
            got.statuses.columns[col].astype(np.float32), want.columns[col][:n].astype(np.float32), err_msg=col
        )
    assert np.isfinite(got.statuses.columns["coulomb1_nm"]).all()


def test_hil_refuses_bad_arguments_naming_them(root, monkeypatch, tmp_path):
    monkeypatch.chdir(root)
    # An ELF that exists (a missing one is refused first, as MissingFileError)
    # and is never run: the arguments are refused before.
    elf = tmp_path / "empty.elf"
    elf.write_bytes(b"")
    with pytest.raises(InputError) as e:
        dw.hil(RUN, T01, drop=2.0, elf=elf)
    assert str(e.value).startswith("drop") and "--" not in str(e.value), str(e.value)
    with pytest.raises(InputError) as e:
        dw.hil(RUN, T01, delay="often", elf=elf)
    assert str(e.value).startswith("delay") and "--" not in str(e.value), str(e.value)
    with pytest.raises(dw.MissingFileError) as e:
        dw.hil(RUN, T01, elf=tmp_path / "none.elf")
    assert str(e.value).startswith("elf: ") and "none.elf" in str(e.value) and "--" not in str(e.value), str(e.value)
