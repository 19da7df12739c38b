"""Processing tool: Create demo survey (easyidp:createdemosurvey)."""
import os

from qgis.core import (QgsProcessingOutputFile, QgsProcessingOutputFolder,
                       QgsProcessingOutputRasterLayer, QgsProcessingOutputVectorLayer,
                       QgsProcessingParameterEnum, QgsProcessingParameterFolderDestination,
                       QgsProcessingParameterNumber)

from .. import presentation
from ..compat import ProcessingNumberParameterType, ProcessingParameterFlag
from ..progress import feedback_progress
from .base import CoreStep, EasyIDPAlgorithm

SIZES = ["small", "medium"]
FIELDS = ["messy", "tidy"]     # FIELD_MESS options: the core's default field, NO_MESS


class CreateDemoSurvey(EasyIDPAlgorithm):
    OUTPUT_FOLDER = "OUTPUT_FOLDER"
    SEED = "SEED"
    SIZE = "SIZE"
    ORTHOMOSAIC = "ORTHOMOSAIC"
    DSM = "DSM"
    PLOTS = "PLOTS"
    POINT_CLOUD = "POINT_CLOUD"
    METASHAPE_PROJECT = "METASHAPE_PROJECT"
    PIX4D_PROJECT = "PIX4D_PROJECT"
    ODM_PROJECT = "ODM_PROJECT"
    OPF_PROJECT = "OPF_PROJECT"
    TRUTH = "TRUTH"
    SEASON_DATES = "SEASON_DATES"
    SEASON_SURVEYS = "SEASON_SURVEYS"
    FIELD_MESS = "FIELD_MESS"

    NAME = "createdemosurvey"
    REQUIRES = ("tifffile", "imagecodecs", "laspy", "lazrs", "plyfile")  # its rasters and clouds
    DISPLAY = "Create demo survey"
    GROUP = "Demo data"
    GROUP_ID = "demo"
    HELP = (
        "Writes a small, complete synthetic drone survey with a known truth, so that every "
        "EasyIDP tool can be tried at once without downloading anything. The survey is a "
        "60 m × 40 m field of 40 plots (UTM 54N):\n"
        "- an orthomosaic (1 cm), a DSM (2 cm) and the plots (GeoPackage and GeoJSON, field "
        "plot_id);\n"
        "- a coloured point cloud (LAZ and PLY);\n"
        "- 36 raw photos of a lawnmower flight, rendered through the camera model;\n"
        "- the same flight as an Agisoft Metashape project, a Pix4D project and an "
        "OpenDroneMap project (odm/, with its opensfm/ files);\n"
        "- LabelMe annotations on four photos;\n"
        "- truth.json: where known ground points are in every photo.\n\n"
        "The same seed gives the same files. Small takes seconds; medium has larger photos.\n\n"
        "Field (advanced): messy (default) gives the field what real ones have: grass in the "
        "margins, weeds in and between the plots, uneven vigour, missing row segments, empty "
        "and lodged plots, shadows, a soil-colour gradient, rows tall and full enough to hide "
        "the soil between them in oblique views, and one block of plots without alleys. Tidy "
        "gives the field of earlier versions: narrow rows on bare soil, nothing else.\n\n"
        "Growth season (advanced): with N dates, also the same field flown on N dates while the "
        "crop grows along known curves, in season/: per date an orthomosaic, a DSM and a point "
        "cloud, a bare-soil DSM, the plots with their variety, surveys.csv (the table for 'Plot "
        "traits over a season') and season_truth.json (height and cover per plot and date).")

    def initAlgorithm(self, config=None):  # noqa: N802 (QGIS API)
        self.addParameter(QgsProcessingParameterFolderDestination(
            self.OUTPUT_FOLDER, self.tr("Output folder")))
        self.add_overwrite_parameter()
        self.addParameter(QgsProcessingParameterEnum(
            self.SIZE, self.tr("Size"), options=[self.tr("small (800 × 600 photos)"),
                                                 self.tr("medium (1600 × 1200 photos)")],
            defaultValue=0))
        p = QgsProcessingParameterNumber(self.SEED, self.tr("Random seed"),
                                         ProcessingNumberParameterType.Integer, defaultValue=0,
                                         minValue=0)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        p = QgsProcessingParameterEnum(
            self.FIELD_MESS, self.tr("Field"),
            options=[self.tr("messy (weeds, margin grass, tall rows, gaps, …)"),
                     self.tr("tidy (narrow rows on bare soil)")], defaultValue=0, optional=True)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        p = QgsProcessingParameterNumber(
            self.SEASON_DATES, self.tr("Growth season: dates flown (0: none)"),
            ProcessingNumberParameterType.Integer, defaultValue=0, minValue=0, maxValue=30)
        p.setFlags(p.flags() | ProcessingParameterFlag.Advanced)
        self.addParameter(p)
        self.addOutput(QgsProcessingOutputFile(self.SEASON_SURVEYS,
                                               self.tr("Season survey table (surveys.csv)")))
        self.addOutput(QgsProcessingOutputRasterLayer(self.ORTHOMOSAIC, self.tr("Orthomosaic")))
        self.addOutput(QgsProcessingOutputRasterLayer(self.DSM, self.tr("DSM")))
        self.addOutput(QgsProcessingOutputVectorLayer(self.PLOTS, self.tr("Plots")))
        self.addOutput(QgsProcessingOutputFile(self.POINT_CLOUD, self.tr("Point cloud (LAZ)")))
        self.addOutput(QgsProcessingOutputFile(self.METASHAPE_PROJECT, self.tr("Metashape project")))
        self.addOutput(QgsProcessingOutputFile(self.PIX4D_PROJECT, self.tr("Pix4D project")))
        self.addOutput(QgsProcessingOutputFolder(self.ODM_PROJECT, self.tr("OpenDroneMap project")))
        self.addOutput(QgsProcessingOutputFile(self.OPF_PROJECT,
                                               self.tr("OPF project (project.opf, PIX4Dmatic)")))
        self.addOutput(QgsProcessingOutputFile(self.TRUTH, self.tr("Truth file")))

    def core_step(self, parameters, context, feedback):
        from ...core.demo import NO_MESS, FieldMess, make_demo_survey

        folder = self.parameterAsString(parameters, self.OUTPUT_FOLDER, context)
        size = SIZES[self.parameterAsEnum(parameters, self.SIZE, context)]
        seed = self.parameterAsInt(parameters, self.SEED, context)
        field = FIELDS[self.parameterAsEnum(parameters, self.FIELD_MESS, context)]
        feedback.pushInfo(self.tr("Writing a {size} demo survey (seed {seed}, {field} field) into "
                                  "{folder}").format(size=size, seed=seed, field=field,
                                                     folder=folder))
        return CoreStep(make_demo_survey, dict(
            folder=folder, seed=seed, size=size, overwrite=self.overwrite(parameters, context),
            progress=feedback_progress(feedback), is_cancelled=feedback.isCanceled,
            field_mess=NO_MESS if field == "tidy" else FieldMess()), {})

    def write_outputs(self, parameters, context, feedback, step, s):
        folder, seed = step.kwargs["folder"], step.kwargs["seed"]
        if context.project() is not None:     # the desktop (qgis_process loads nothing)
            group = presentation.MapGroup(self.tr("Demo survey"), expanded=True)
            for rank, (path, name, out, hint, style) in enumerate((
                    (s.plots_gpkg, self.tr("Demo plots"), self.PLOTS, presentation.VECTOR,
                     plots_style()),
                    (s.orthomosaic, self.tr("Demo orthomosaic"), self.ORTHOMOSAIC,
                     presentation.RASTER, None),
                    (s.dsm, self.tr("Demo DSM"), self.DSM, presentation.RASTER, None))):
                presentation.load_files(self, context, feedback, context.project(), [path], [name],
                                        hint, group, out, style=style, first_rank=rank)
        out = {}
        dates = self.parameterAsInt(parameters, self.SEASON_DATES, context)
        if dates:
            from ...core.demo import make_demo_season
            season = make_demo_season(os.path.join(folder, "season"), dates=dates, seed=seed,
                                      is_cancelled=feedback.isCanceled)
            feedback.pushInfo(self.tr("Growth season: {n} dates in {f}").format(
                n=len(season.dates), f=season.folder))
            out[self.SEASON_SURVEYS] = season.surveys
        feedback.pushInfo(self.tr("Demo survey written in {seconds:.1f} s: {n_photos} photos, "
                                  "{n_plot_ids} plots, {dates} season dates, in {folder}.").format(
                              seconds=s.seconds, n_photos=len(s.photos),
                              n_plot_ids=len(s.plot_ids), dates=dates, folder=folder))
        return {**out, self.OUTPUT_FOLDER: folder, self.ORTHOMOSAIC: s.orthomosaic, self.DSM: s.dsm,
                self.PLOTS: s.plots_gpkg, self.POINT_CLOUD: s.point_cloud_laz,
                self.METASHAPE_PROJECT: s.metashape_project, self.PIX4D_PROJECT: s.pix4d_project,
                self.ODM_PROJECT: s.odm_project, self.OPF_PROJECT: s.opf_project,
                self.TRUTH: s.truth}


def plots_style():
    """Plot outlines in yellow, no fill, labelled with plot_id when zoomed in."""
    return presentation.outline_style("#ffd400", 0.5, label='"plot_id"', label_scale=1000,
                                      label_priority=3)
