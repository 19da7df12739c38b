"""The per-pixel occlusion test of the plot statistics: for each photo, which pixels of each of
its records have a line of sight that meets the DSM outside the ROI (:mod:`.pixel_occlusion`)."""
from typing import List

from ..errors import EasyIDPError
from ..raster import as_dsm
from .pixel_occlusion import PixelJob, rings_in_dsm_crs, test_pixels


class PhotoOcclusion:
    """The per-pixel occlusion test of each photo's records (:mod:`.pixel_occlusion`)."""

    def __init__(self, result, recon, rois, dsm, distortion, samples):
        if recon is None or rois is None:
            raise EasyIDPError("The occlusion test of the photo pixels needs the photogrammetry "
                               "project and the ROIs as well as the DSM.")
        names = list(rois.names)
        if names != list(result.roi_names):
            raise EasyIDPError("The ROIs given are not those of the back-projection (names or "
                               "order differ): give the ROI set it was made from.")
        self.recon, self.distortion, self.samples = recon, distortion, int(samples)
        self.surface = as_dsm(dsm).ray_surface()
        self.rings = rings_in_dsm_crs(rois, self.surface, sorted(set(result.roi.tolist())))
        self.cams = {}
        for label in result.photo_labels:
            try:
                self.cams[label] = recon.camera(label)
            except EasyIDPError:
                raise EasyIDPError(f"Photo {label} of the back-projection is not a camera of "
                                   f"{recon.source}: give the project it was made with.") from None
        self.result = result
        self.rays = 0
        self.undecided = 0

    def photo(self, j, recs, windows, prog):
        jobs = [PixelJob(int(self.result.roi[i]), r0, c0, mask) for i, (r0, c0, mask) in
                zip(recs, windows)]
        test_pixels(jobs, self.recon, self.cams[self.result.photo_labels[j]], self.surface,
                    self.rings, distortion=self.distortion, coarse=self.samples,
                    is_cancelled=prog.cancelled)
        self.rays += sum(jb.rays for jb in jobs)
        self.undecided += sum(jb.undecided for jb in jobs)
        return [(jb.occluded, jb.undecided) for jb in jobs]

    def notes(self) -> List[str]:
        out = [f"occlusion per pixel: {self.rays:,} lines of sight cast"]
        if self.undecided:
            out.append(f"{self.undecided:,} pixel(s) whose line of sight met no DSM data were "
                       "kept (undecided)")
        return out
