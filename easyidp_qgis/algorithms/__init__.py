"""One module per Processing tool; ALGORITHMS lists the classes the provider registers."""
from .back_project_rois import BackProjectROIs
from .camera_footprints import CameraFootprints
from .create_demo_survey import CreateDemoSurvey
from .create_plot_grid import CreatePlotGrid
from .crop_point_cloud_by_rois import CropPointCloudByROIs
from .crop_raster_by_rois import CropRasterByROIs
from .fit_plot_grid import FitPlotGrid
from .export_training_set import ExportTrainingSet
from .forward_project_polygons import ForwardProjectPolygons
from .orthorectify_rois import OrthorectifyROIs
from .photo_statistics import PhotoStatisticsAlgorithm
from .point_cloud_roi_statistics import PointCloudROIStatistics
from .roi_heights_from_dsm import ROIHeightsFromDSM
from .season_traits import SeasonTraits

ALGORITHMS = [CropRasterByROIs, ROIHeightsFromDSM, CameraFootprints, CropPointCloudByROIs,
              PointCloudROIStatistics, CreateDemoSurvey, SeasonTraits, BackProjectROIs,
              ForwardProjectPolygons, OrthorectifyROIs, PhotoStatisticsAlgorithm, CreatePlotGrid,
              FitPlotGrid, ExportTrainingSet]
