"""The values a photo tool reads, shared by every tool that reads photo pixels (Plot
statistics, Back-project ROIs' crops, Orthorectify ROIs): VALUES (as stored, temperature in
°C, reflectance), the FLIR object parameters, the temperature TIFFs' preset, scale and offset,
and the core ``values`` and ``value_options`` they give (:func:`core.radiometry.read_photo_values`)."""
from qgis.core import QgsProcessingParameterEnum, QgsProcessingParameterNumber

from .compat import ProcessingNumberParameterType, ProcessingParameterFlag
from .parameters import optional_number, translatable

VALUES = "VALUES"
TEMPERATURE_PRESET = "TEMPERATURE_PRESET"
TEMPERATURE_SCALE = "TEMPERATURE_SCALE"
TEMPERATURE_OFFSET = "TEMPERATURE_OFFSET"
VALUE_CHOICES = ("stored", "temperature", "reflectance")
PRESET_CHOICES = ("degC", "K", "ddegC", "mdegC", "cK")


# (parameter, core option, label): the object parameters of FLIR photos (empty: the photo's)
OBJECT_PARAMETERS = (
    ("EMISSIVITY", "emissivity", translatable("Emissivity (empty: the photo's)")),
    ("OBJECT_DISTANCE", "object_distance", translatable("Object distance, m (empty: the photo's)")),
    ("REFLECTED_TEMPERATURE", "reflected_temperature",
     translatable("Reflected apparent temperature, °C (empty: the photo's)")),
    ("ATMOSPHERIC_TEMPERATURE", "atmospheric_temperature",
     translatable("Atmospheric temperature, °C (empty: the photo's)")),
    ("RELATIVE_HUMIDITY", "relative_humidity", translatable("Relative humidity, % (empty: the photo's)")),
    ("IR_WINDOW_TEMPERATURE", "ir_window_temperature",
     translatable("IR window temperature, °C (empty: the photo's)")),
    ("IR_WINDOW_TRANSMISSION", "ir_window_transmission",
     translatable("IR window transmission, 0–1 (empty: the photo's)")),
)


def add_value_parameters(alg, label: str):
    """VALUES (labelled ``label``, translated), the object parameters, TEMPERATURE_PRESET,
    TEMPERATURE_SCALE and TEMPERATURE_OFFSET (advanced), all optional: as stored by default."""
    alg.addParameter(QgsProcessingParameterEnum(
        VALUES, alg.tr(label),
        [alg.tr("As stored"), alg.tr("Temperature (°C)"), alg.tr("Reflectance")],
        defaultValue=0, optional=True))
    for name, _option, text in OBJECT_PARAMETERS:
        p = QgsProcessingParameterNumber(name, alg.tr(text), ProcessingNumberParameterType.Double,
                                         optional=True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        alg.addParameter(p)
    p = QgsProcessingParameterEnum(
        TEMPERATURE_PRESET, alg.tr("Temperature TIFFs store"),
        [alg.tr("°C"), alg.tr("Kelvin"), alg.tr("°C × 10"), alg.tr("°C × 1000"),
         alg.tr("Centi-kelvin (K × 100)")], defaultValue=0, optional=True)
    p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
    alg.addParameter(p)
    for name, text, help_text in (
            (TEMPERATURE_SCALE, translatable("Temperature TIFF scale (°C = stored × scale + offset)"),
             translatable("Empty: the preset's")),
            (TEMPERATURE_OFFSET, translatable("Temperature TIFF offset, °C (empty: the preset)"), "")):
        p = QgsProcessingParameterNumber(name, alg.tr(text), ProcessingNumberParameterType.Double,
                                         optional=True)
        if help_text:
            p.setHelp(alg.tr(help_text))
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        alg.addParameter(p)


def value_parameters(alg, parameters, context):
    """The core's keyword arguments ``values`` (the VALUES chosen) and ``value_options`` (the
    object parameters given, the temperature TIFFs' preset, scale and offset)."""
    values = VALUE_CHOICES[alg.parameterAsEnum(parameters, VALUES, context)]
    opts = {option: optional_number(alg, parameters, name, context)
            for name, option, _label in OBJECT_PARAMETERS}
    if opts["relative_humidity"] is not None:             # the tools take percent
        opts["relative_humidity"] /= 100.0
    opts["temperature_preset"] = PRESET_CHOICES[
        alg.parameterAsEnum(parameters, TEMPERATURE_PRESET, context)]
    opts["temperature_scale"] = optional_number(alg, parameters, TEMPERATURE_SCALE, context)
    opts["temperature_offset"] = optional_number(alg, parameters, TEMPERATURE_OFFSET, context)
    return {"values": values, "value_options": opts}
