"""SSP 1.0 parameter-set files (.ssv) as fmpy start values.

`damper calibrate` writes DIR/parameters.ssv (SystemStructureParameterValues); `read_ssv` turns one
into a `{name: value}` dict for `fmpy.simulate_fmu(..., start_values=...)` or `Slave.initialize`:

    start = read_ssv("out/cal/parameters.ssv")
    simulate_fmu("target/fmu/SemiActiveDamper.fmu", start_values=start, ...)

Real values become float, Integer int, Boolean bool; other value types and malformed files raise
ValueError naming the file and the parameter. Standard library only.
"""

import xml.etree.ElementTree as ET
from pathlib import Path

SSV = "http://ssp-standard.org/SSP1/SystemStructureParameterValues"


def read_ssv(path: str | Path) -> dict[str, float | int | bool]:
    """The parameters of an SSP 1.0 .ssv file, in file order."""
    path = Path(path)
    root = ET.parse(path).getroot()
    if root.tag != f"{{{SSV}}}ParameterSet":
        raise ValueError(f"{path}: the root element is {root.tag}, not an ssv:ParameterSet of {SSV}")
    values: dict[str, float | int | bool] = {}
    for p in root.iterfind(f"{{{SSV}}}Parameters/{{{SSV}}}Parameter"):
        name = p.get("name")
        if not name:
            raise ValueError(f"{path}: an ssv:Parameter without a name")
        if name in values:
            raise ValueError(f"{path}: parameter {name} is given twice")
        real, integer, boolean = (p.find(f"{{{SSV}}}{k}") for k in ("Real", "Integer", "Boolean"))
        try:
            if real is not None:
                values[name] = float(real.get("value", ""))
            elif integer is not None:
                values[name] = int(integer.get("value", ""))
            elif boolean is not None:
                text = boolean.get("value", "")
                if text not in ("true", "false", "1", "0"):
                    raise ValueError(text)
                values[name] = text in ("true", "1")
            else:
                raise ValueError(f"{path}: parameter {name} has no Real, Integer or Boolean value")
        except ValueError as e:
            raise ValueError(f"{path}: parameter {name}: bad value ({e})") from None
    return values
