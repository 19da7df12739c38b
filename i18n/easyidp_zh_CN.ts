<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="zh_CN">
  <context>
    <name>EasyIDP</name>
    <message>
      <source>Back-project ROIs to raw photos</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Projection</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Finds every ROI (plot, tree, plant polygon) in every raw photo of a Metashape or Pix4D project that sees it, using the cameras the project solved (EasyIDP's back2raw). Raw photos are sharper than the orthomosaic and free of its seamlines.

Inputs: the ROI polygons; the project (Metashape .psx/.psz/cameras .xml, Pix4D .p4d or any file of its 1_initial/params folder); the height of the ROI vertices, from the geometry's Z (e.g. the output of ROI heights from DSM), a DSM sampled at every vertex, a numeric attribute, or one ground height (heights in the project's vertical reference; for a Metashape chunk in a geographic CRS: ellipsoidal). Photos folder: where the photos are when they moved (matched by file name).

Each ROI is densified, projected with the lens distortion, and clipped to the photo frame (or, with 'whole ROIs only', kept only where the whole ROI is in the photo). With a DSM, lines of sight to points on the surface inside the ROI are tested for occlusion. Photos showing less than the minimum visible, unoccluded share are dropped; the others are ranked by a score (view angle, ground resolution, distance from the photo centre, visible share).

Outputs: the ROIs in photo pixels (x = column, y = −row: they lie on a raw photo opened in QGIS without georeference; filter by 'photo'), one feature per ROI × photo with score, rank, view angle, GSD and fractions; a summary of the ROIs in the map with their photo count and best photo; optionally EasyIDP's JSON {roi: {photo: [[x, y], ...]}}, the crops of the raw photos (PNG with the ROI as alpha, TIFF for 16-bit or multiband photos, each with a JSON sidecar) and one preview PNG per ROI showing its best photos.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Apply the lens distortion (off for undistorted photos)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Margin around the crops (pixels)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROIs</source>
      <translation>感兴趣区</translation>
    </message>
    <message>
      <source>ROIs (polygons)</source>
      <translation>感兴趣区（多边形）</translation>
    </message>
    <message>
      <source>Name field (default: feature id)</source>
      <translation>名称字段（默认：要素 ID）</translation>
    </message>
    <message>
      <source>Heights of the ROI vertices</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>DSM (GeoTIFF): vertex heights and occlusion test</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Height attribute</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Photos folder (when the photos moved; matched by file name)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROIs partly outside a photo</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Test occlusion against the DSM (when a DSM is given)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Minimum visible, unoccluded share of a ROI in a photo</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Best photos to keep per ROI (0 = all)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROIs in photo pixels (x = column, y = −row)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROIs with their photo count and best photo</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>EasyIDP back2raw JSON</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Crops of the raw photos</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Preview per ROI (its best photos)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>No DSM given: occlusion is not tested.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Cutting the ROIs out of the photos…</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Geometry Z (3-D polygons)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>DSM, sampled at every vertex</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Attribute (one height per ROI)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Constant ground height</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Constant ground height (project vertical reference)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Clip them to the photo frame</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Drop the photo (whole ROIs only)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>DSM</source>
      <translation>DSM</translation>
    </message>
    <message>
      <source>Projecting {n} ROIs into {m} photos ({h})</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{rois} in the photos of {project} (photo pixels)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{rois}: photos of {project} that see them</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{k} ROI × photo pairs for {seen} of {n} ROIs; {u} ROIs in no photo.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Heights from the DSM: choose the DSM raster, or another height source.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROI '{name}': {why}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>… and {n} more ROIs without a photo</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} crops and {p} previews written.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Heights from an attribute: choose the height attribute of the ROI layer.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Constant ground height: give the height, or choose another height source.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Photo {label} skipped: {why}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Overwrite existing files (otherwise the tool stops before writing anything when an output already exists)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Camera positions and footprints</source>
      <translation>相机位置与地面覆盖范围</translation>
    </message>
    <message>
      <source>Photogrammetry projects</source>
      <translation>摄影测量工程</translation>
    </message>
    <message>
      <source>Reads the solved cameras of an Agisoft Metashape project (.psx with its .files folder, .psz, or an exported cameras .xml), a Pix4D project (.p4d, the project folder or its 1_initial/params folder: choose any file in it, e.g. *_pmatrix.txt) or an OpenDroneMap/OpenSfM project (choose opensfm/reconstruction.json in the ODM project folder; Python scripts may give the folder itself) and draws, for every aligned camera, its position and the part of the ground its photo sees. Run it first to check that a project was read right.

Chunk: the Metashape chunk (label or index), or the OpenSfM reconstruction (index of a partial model; by default the largest, as the log says).

The footprint is the photo border (densified, with the lens distortion) cast onto the DSM, or onto a constant ground height when no DSM is given. Attributes: label, photo path, enabled, height above ground (m), view angle from nadir (degrees), and for footprints the area (m²) and whether the whole border reached the ground's data (complete; where the DSM ends the footprint continues on a plane at the ground height under the camera). A camera at or below the ground gets no footprint and is named in the log.

Metashape projects with rolling-shutter compensation: each photo has one pose per image row (the motion Metashape estimated during the readout); the footprints, like every projection, use it, and the log says when it is applied.

Outputs are in the output CRS if one is chosen, else in the DSM's CRS, else in the map's CRS, else in the photogrammetry project's (the log says which). A Pix4D params folder without *_wkt.prj needs the project CRS. ODM projects bring ODM's CRS (that of its orthophoto and DSM); an OpenSfM dataset without ODM uses the WGS 84 / UTM zone of its reference point unless a project CRS is set. Heights of the DSM or the ground height must be in the project's vertical reference (for a Metashape chunk in a geographic CRS: ellipsoidal heights; for ODM: the heights of its DSM).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Output CRS (default: the DSM's, else the map's, else the photogrammetry project's)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>DSM (GeoTIFF) for the footprints</source>
      <translation>用于覆盖范围的 DSM（GeoTIFF）</translation>
    </message>
    <message>
      <source>Camera positions</source>
      <translation>相机位置</translation>
    </message>
    <message>
      <source>Camera footprints</source>
      <translation>相机地面覆盖范围</translation>
    </message>
    <message>
      <source>the output CRS chosen</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>the DSM's CRS</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>the map's CRS</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} camera(s) have no DSM right under them: their height above ground is taken from the DSM where their photo sees the ground.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} camera(s) see no DSM at all: their height above ground is taken from the median ground under the other cameras.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground height when no DSM is given (project vertical reference)</source>
      <translation>未提供 DSM 时的地面高度（工程高程基准）</translation>
    </message>
    <message>
      <source>Give a DSM or a ground height: the footprints are where the photos meet the ground.</source>
      <translation>请提供 DSM 或地面高度：覆盖范围是照片与地面相交之处。</translation>
    </message>
    <message>
      <source>Camera footprints of {project}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Cameras of {project}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Outputs in {crs} (the photogrammetry project's CRS).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} cameras and {f} footprints written.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>The project is in a local coordinate system ({name}): the outputs will not line up with map layers.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} camera(s) are at or below the ground, so they have no footprint: {names}. Check the ground height or the DSM and its vertical reference.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} footprint(s) reach beyond the DSM's data: there they continue on a plane at the ground height under the camera (attribute complete = false).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Outputs in {crs} ({why}).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Create demo survey</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Demo data</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Writes a small, complete synthetic drone survey with a known truth, so that every EasyIDP tool can be tried at once without downloading anything. The survey is a 60 m × 40 m field of 40 plots (UTM 54N):
- an orthomosaic (1 cm), a DSM (2 cm) and the plots (GeoPackage and GeoJSON, field plot_id);
- a coloured point cloud (LAZ and PLY);
- 36 raw photos of a lawnmower flight, rendered through the camera model;
- the same flight as an Agisoft Metashape project, a Pix4D project and an OpenDroneMap project (odm/, with its opensfm/ files);
- LabelMe annotations on four photos;
- truth.json: where known ground points are in every photo.

The same seed gives the same files. Small takes seconds; medium has larger photos.

Growth season (advanced): with N dates, also the same field flown on N dates while the crop grows along known curves, in season/: per date an orthomosaic, a DSM and a point cloud, a bare-soil DSM, the plots with their variety, surveys.csv (the table for 'Plot traits over a season') and season_truth.json (height and cover per plot and date).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Random seed</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Growth season: dates flown (0: none)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Output folder</source>
      <translation>输出文件夹</translation>
    </message>
    <message>
      <source>Size</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Season survey table (surveys.csv)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Orthomosaic</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Plots</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Point cloud (LAZ)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Metashape project</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Pix4D project</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>OpenDroneMap project</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Truth file</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Demo survey</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Writing a {size} demo survey (seed {seed}) into {folder}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Demo survey written in {seconds:.1f} s: {n_photos} photos, {n_plot_ids} plots, {dates} season dates, in {folder}.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>small (800 × 600 photos)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>medium (1600 × 1200 photos)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Demo plots</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Demo orthomosaic</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Demo DSM</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Growth season: {n} dates in {f}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Crop point cloud by ROIs</source>
      <translation>按感兴趣区裁剪点云</translation>
    </message>
    <message>
      <source>Cropping</source>
      <translation>裁剪</translation>
    </message>
    <message>
      <source>Cuts every ROI (plot, tree, plant polygon) out of a point cloud (.las, .laz or .ply, e.g. the dense cloud of Pix4D or Metashape) into one file per ROI in the output folder, named after the name field (made safe for file names and unique).

A point belongs to an ROI when its x, y is inside the polygon (holes and multipart polygons honoured) and, if set, its Z is within the Z range (advanced: e.g. to drop noise below the ground or above the canopy). A point inside overlapping ROIs goes to each. The cloud is read once and every point is tested only against the ROIs near it, so thousands of ROIs on a large cloud are fast.

Every point attribute is kept (colour, intensity, classification, returns, GPS time, normals, extra dimensions) with the exact coordinates. LAS/LAZ files carry their CRS; a PLY file has none, so give the 'Point cloud CRS' for it (and for a LAS file without a CRS). ROIs in another CRS are reprojected to the cloud's.

ROIs outside the cloud are named in the log and skipped; ROIs over the cloud without any point are reported and get no file unless 'Write empty files' is checked. Cropped LAS/LAZ files load into the map when this QGIS can display point clouds (PDAL provider).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Same as input</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>LAZ (compressed LAS)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Index of the crops (optional): the ROIs with the file ('crop_file'), the number of points ('points') and the outcome ('crop_status') of each. When it is opened after the run (or 'Load layers on completion' is ticked in batch mode, or it is a model output set to open), up to 100 LAS/LAZ crops are loaded too, in one collapsed group below the ROI layer, where this QGIS can display point clouds (PDAL provider).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Write empty files for ROIs without any point</source>
      <translation>为没有点的感兴趣区写出空文件</translation>
    </message>
    <message>
      <source>Index of the crops (open it to see the crops)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Index of the point cloud crops</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Output format</source>
      <translation>输出格式</translation>
    </message>
    <message>
      <source>Cropped point clouds</source>
      <translation>裁剪后的点云</translation>
    </message>
    <message>
      <source>Number of ROIs cropped</source>
      <translation>已裁剪的感兴趣区数量</translation>
    </message>
    <message>
      <source>Number of ROIs without points</source>
      <translation>没有点的感兴趣区数量</translation>
    </message>
    <message>
      <source>Number of ROIs outside the cloud</source>
      <translation>点云范围外的感兴趣区数量</translation>
    </message>
    <message>
      <source>The cropped point clouds are not loaded into the map: this QGIS has no point cloud provider (PDAL). Open them from the output folder (e.g. in CloudCompare).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>PLY crops are not loaded into the map; open them from the output folder.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Cropping {n_rois} ROIs into {folder}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Point cloud crops of {cloud} ({n})</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{cropped} ROIs cropped ({points:,} points), {n_empty} without points, {n_missed} outside the cloud.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>None of the {n_items} ROIs overlaps the point cloud: check that the ROIs and the cloud are in the right CRS (set 'Point cloud CRS' if the file has none or a wrong one).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Crop raster by ROIs</source>
      <translation>按感兴趣区裁剪栅格</translation>
    </message>
    <message>
      <source>Cuts every ROI (plot, tree, plant polygon) out of a GeoTIFF raster: an orthomosaic (DOM), a surface model (DSM) or a multispectral map, into one GeoTIFF per ROI in the output folder, named after the name field (made safe for file names and unique).

The raster is read in a single pass, each tile or strip once, so thousands of ROIs on rasters larger than memory are fast. Crops keep the raster's pixel grid, CRS and data type. Pixels outside the ROI are masked: RGB gets an alpha band, RGBA its alpha combined, DSM and multispectral get nodata (the raster's own, or -32767 for floating point and the type's extreme for integers when it has none). A pixel belongs to an ROI when its centre is inside (GDAL's rule); 'All touched' takes every pixel the ROI touches. Holes and multipart polygons are honoured. ROIs in another CRS are reprojected; ROIs outside the raster are reported and skipped.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Index of the crops (optional): the ROIs with the file of each ('crop_file', empty for a skipped ROI) and 'crop_status'. When it is opened after the run (or 'Load layers on completion' is ticked in batch mode, or it is a model output set to open), up to 100 crops are loaded too, in one collapsed group below the ROI layer.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>All touched (include every pixel the ROI touches)</source>
      <translation>全部接触（包含感兴趣区接触到的所有像元）</translation>
    </message>
    <message>
      <source>Raster</source>
      <translation>栅格</translation>
    </message>
    <message>
      <source>Index of the crops</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Raster (GeoTIFF: orthomosaic, DSM or multispectral)</source>
      <translation>栅格（GeoTIFF：正射影像、DSM 或多光谱）</translation>
    </message>
    <message>
      <source>Cropped rasters</source>
      <translation>裁剪后的栅格</translation>
    </message>
    <message>
      <source>Number of ROIs skipped</source>
      <translation>跳过的感兴趣区数量</translation>
    </message>
    <message>
      <source>Cropping {n_rois} ROIs out of {raster} into {folder}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Crops of {raster} ({n})</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n_files} GeoTIFFs written, {n_skipped} ROIs skipped.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROI '{name}' skipped: {reason}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Forward-project photo polygons to the map</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Brings polygons drawn or detected on the raw photos (LabelMe, COCO, YOLO, or the photo-pixel layer written by Back-project ROIs) to the map, with their true position, area and perimeter: every vertex's pixel becomes a ray through the solved camera (lens distortion included) and its first hit on the DSM is the vertex on the map. Exact on any terrain and canopy (not a flat-ground homography).

Input, one of: a file (LabelMe .json, COCO .json, YOLO .txt); a folder (LabelMe .json files or YOLO .txt files, with classes.txt or data.yaml for class names); or a photo-pixel layer (x = column, y = −row, field 'photo'). Each image is matched to a photo of the project by file name; an image that is not in the project, or whose size differs from the camera's, is refused with its name.

Edges are densified in the photo (a vertex every few pixels) so that long edges follow the surface. A vertex whose ray misses the DSM, leaves it or enters nodata is dropped and its polygon marked complete = false (and reported), never silently reshaped.

Merge: 'none' keeps one polygon per photo; 'union' merges the overlapping polygons of one label from several photos into one; 'best' keeps the best view (complete, highest score, most nadir). Fields: photo, label, score, area_m2 and perimeter_m (planimetric, metres), views, complete, missing (vertices without a hit). Output in the DSM's CRS, heights from the DSM.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Annotation file (LabelMe .json, COCO .json or YOLO .txt)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>…or a folder of LabelMe .json or YOLO .txt files</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>…or a photo-pixel polygon layer (x = column, y = −row)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>DSM (GeoTIFF)</source>
      <translation>数字表面模型 DSM（GeoTIFF）</translation>
    </message>
    <message>
      <source>Merge the same object seen in several photos</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Densify edges: a vertex every … photo pixels (0: off)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Polygons on the map</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Give exactly one input: an annotation file, a folder of annotation files, or a photo-pixel layer.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{what} on the map (through {project} onto {dsm})</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} polygons from {p} photos written to the map ({i} incomplete).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>None (one polygon per photo)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Union of the views</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Best view</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} lines or points skipped: only polygons are forward-projected by this tool.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>'{label}' is incomplete ({why}).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Orthorectify ROIs from raw photos</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Makes, for every ROI, a georeferenced image from a raw photo instead of the orthomosaic: sharper (no blending, ghosting or seamlines) and with true geometry. Each output pixel's ground point (its height from the DSM) is projected into the photo with the solved camera (lens distortion included) and the photo is sampled there (bilinear).

Photos: 'best' takes the best-scored photo of each ROI (the backward projection's score: visible share, view angle, resolution, distance from the centre); 'all' writes one image per photo that sees the ROI; 'named photo' uses the photo given. Pixel size: the GSD given (DSM CRS units), or 0 for the photo's native resolution at the ROI.

Output pixels outside the ROI, on DSM nodata, outside the photo, or hidden from the camera by the DSM (occlusion) are transparent (alpha 0). One GeoTIFF per ROI (and photo, for 'all') in the output folder, in the DSM's CRS, with the photo's bands plus alpha. The photos are read from the paths stored in the project, or from the photos folder when given (matched by file name).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Index of the images (optional): one feature per image, the ROI with its file ('image_file'), photo, visible share and pixel size. When it is opened after the run (or 'Load layers on completion' is ticked in batch mode, or it is a model output set to open), up to 100 images are loaded too, in one collapsed group below the ROI layer.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Pixel size (DSM CRS units; 0: the photo's native resolution)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Index of the images (open it to see the images)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Index of the images</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Folder of the raw photos (default: the paths in the project)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Photos</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Photo label (for 'A named photo')</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Orthorectified ROI images</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Number of images written</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{rois} from raw photos ({n})</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} orthorectified ROI images written to {folder}; {s} skipped.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Best photo of each ROI</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Every photo that sees the ROI</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>A named photo</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{what}: no image ({why}).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Point cloud statistics per ROI</source>
      <translation>按感兴趣区统计点云</translation>
    </message>
    <message>
      <source>Heights</source>
      <translation>高度</translation>
    </message>
    <message>
      <source>For every ROI (plot, tree, plant polygon), the points of a point cloud (.las, .laz or .ply) inside it and their heights above the ground: canopy height, its percentiles and the point density, e.g. for plant height or biomass models.

The result is the ROI layer with its attributes and: count (points inside), density (points per square unit of the cloud's CRS: per m² for a cloud in metres), z_min, z_mean, z_max (the points' Z), ground (the mean ground Z under the points), h_mean, h_max and h_pNN (height above the ground: Z minus ground) for each height percentile asked (default 5, 50, 95, 99; p99 is a robust canopy top).

Ground: a DSM/DTM raster sampled under every point (a bare-soil DSM flown before emergence, or a DTM); or a single ground height; or, with neither, each ROI's own lowest points: the given percentile of its Z (advanced, default 1). The raster and the height must be in the cloud's Z units and vertical reference.

LAS/LAZ files carry their CRS; a PLY file has none, so give the 'Point cloud CRS' for it (and for a LAS file without a CRS). ROIs in another CRS are reprojected. ROIs without any point are named in the log; their count and density are 0 and their Z and heights empty (NULL), never 0.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: DSM/DTM raster (GeoTIFF; optional)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground without raster or height: this percentile of each ROI's Z</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Height percentiles (comma separated)</source>
      <translation>高度百分位数（逗号分隔）</translation>
    </message>
    <message>
      <source>ROIs with point cloud statistics</source>
      <translation>带点云统计的感兴趣区</translation>
    </message>
    <message>
      <source>Ground: give either a DSM/DTM raster or one ground height, not both.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground DSM/DTM</source>
      <translation>地面 DSM/DTM</translation>
    </message>
    <message>
      <source>The ROI layer's own fields with the names of the statistics are replaced by the new values.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: one height for all ROIs (cloud Z units; optional)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{rois}: point cloud heights of {cloud}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Statistics of {n_rois} ROIs written, {n} with points{shown}.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: the raster {name} under every point.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: percentile {ground_pct:g} of each ROI's Z.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>The ground raster {name} has no data under the points of {n} of the {total} ROIs (outside it or nodata): their heights above ground are empty. Check that it covers the ROIs.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>None of the {n_rois} ROIs contains a point of the cloud: check that the ROIs and the cloud are in the right CRS (set 'Point cloud CRS' if the file has none or a wrong one) and the Z range.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} ROI(s) contain no point (outside the cloud, in a gap, or outside the Z range); their statistics are empty: feature id {ids}.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: {height:g} for every ROI.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source> (map colours: {field})</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROI heights from DSM</source>
      <translation>从 DSM 获取感兴趣区高度</translation>
    </message>
    <message>
      <source>Gives every ROI its height from a surface model (DSM), as the Z of its vertices and as the attribute 'height' (in the DSM's units and vertical reference). The result is the ROI layer as PolygonZ, ready for backward projection into raw photos.

Per polygon: the statistic (mean, median, min, max, a percentile, e.g. 90 for canopy top, 5 for ground, the standard deviation, or EasyIDP's pmin/pmax: the mean of the values below the percentile / above 100 minus the percentile) of the DSM pixels whose centres are inside the ROI, grown by a positive buffer or shrunk by a negative one (map units of the DSM). Every vertex gets that height.
Per vertex: the DSM height at each vertex (bilinear or nearest pixel), or, with a buffer, the statistic of the pixels within the buffer distance of the vertex; 'height' is then the mean of the vertex heights.

Nodata pixels are ignored. An ROI without any valid pixel keeps an empty (NULL) height and NaN Z, and is listed in the log; it never gets 0.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Per polygon: one statistic of the DSM pixels inside</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Per vertex: the DSM height at each vertex</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Vertex sampling</source>
      <translation>顶点采样</translation>
    </message>
    <message>
      <source>Mode</source>
      <translation>模式</translation>
    </message>
    <message>
      <source>Statistic</source>
      <translation>统计量</translation>
    </message>
    <message>
      <source>Buffer (DSM map units; negative shrinks the polygon)</source>
      <translation>缓冲距离（DSM 地图单位；负值收缩多边形）</translation>
    </message>
    <message>
      <source>ROIs with heights</source>
      <translation>带高度的感兴趣区</translation>
    </message>
    <message>
      <source>Percentile (0–100, for the percentile, pmin and pmax statistics)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{rois}: height {what} from {dsm}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROI '{name}': {reason}; its height is left empty.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Heights ({what}) of {n} ROIs: {lo:.3f} to {hi:.3f} (DSM units), {null} empty (NULL).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Heights of {n} ROIs: all empty (NULL): the DSM has no valid pixel under any of them.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Plot traits over a season</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Time series</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Traits of every ROI (plot, tree) on every date of a season of surveys: plant height from the DSMs, canopy cover, band means and a vegetation index from the orthomosaics, heights from the point clouds. Each file is read once for all ROIs; the files are shared out to worker processes on this computer, or to a Dask cluster.

Survey table: a CSV file or a table layer with the columns date (YYYY-MM-DD), orthomosaic, dsm, point_cloud and project (file paths, absolute or relative to the table's folder; empty cells allowed); optional: bands (the orthomosaic's band names in order, e.g. blue,green,red,rededge,nir: NDVI needs red and nir) and crs (for files without one, e.g. PLY). Rows with a missing file, an unreadable raster or a CRS that cannot be related to the ROIs are reported by row and left out; the rest completes. The project column is read but not used by the traits yet.

Traits: height_pNN (percentiles of the DSM above the ground, metres); cover (share of the ROI whose vegetation index is above the threshold, 0-1; Otsu's automatic threshold per orthomosaic, or a given one); exg (excess green, RGB) or ndvi (named bands); mean_&lt;band&gt; (band means); cloud_points and cloud_height_pNN (point clouds).

Ground: a bare-soil DSM or DTM of the season (a flight before emergence): a plane is fitted to it under each ROI. Without one, each ROI's ground is the plane through the lowest heights (the given percentile) in a 3 × 3 grid over it, which needs bare soil between the plants.

Workers: processes on this computer. Dask scheduler (advanced): tcp://host:8786 to run on a Dask cluster (the files must be at the same paths on every worker), or 'local' for a Dask cluster of 'Workers' processes on this computer.

Outputs: the long table (roi, date, trait, value); the ROIs with the traits of their latest date (styled by height); growth curves as a PNG (a panel per ROI, or per group when there are many ROIs and a group field); optionally the crops, in &lt;date&gt;/&lt;orthomosaic|dsm|point_cloud&gt;/ folders.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Dask scheduler (tcp://host:port, or 'local'; empty: processes here)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Survey table (CSV file or table layer)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Name field (unique; default: feature id)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Group field (treatment, variety: colours the curves)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Traits</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: bare-soil DSM or DTM of the season (optional)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground without a DTM: percentile of each ROI's lowest heights</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Cover threshold on the vegetation index (empty: Otsu per orthomosaic)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Worker processes</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Crops per date (optional folder)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Traits per ROI and date (long table)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>ROIs with their latest traits</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Growth curves (PNG)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>PNG files (*.png)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Survey table: no table given, or it could not be loaded.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Traits: choose at least one.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>No trait could be computed: every survey row was left out (see the messages above).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} surveys, {r} ROIs, traits: {t}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{v} values of {k} traits for {r} ROIs on {d} dates in {s:.0f} s ({e}); {p} rows or files left out.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{rois}: latest traits</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{rois}: traits per date</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Height from the DSM</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Canopy cover</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Band means</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Vegetation index (ExG or NDVI)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Heights from the point cloud</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Survey {p}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Left out: {p}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>QGIS's own {packages}: the plugin does not replace QGIS's packages; use a newer QGIS.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{tool} needs Python packages that QGIS's Python does not have: {packages}.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Nothing was installed.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>The plugin's Python packages are installed with the Install button the QGIS desktop shows when one is missing, or by running:
{command}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{name} {version} (needs {spec})</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{python} is Python {got}, but QGIS runs Python {want}; QGIS's own interpreter was not found</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{error}. Install the missing Python package for QGIS's Python ({python}).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>QGIS's Python interpreter {python} cannot run: {error}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>To install them, click Install in the EasyIDP message bar of the QGIS desktop, or run:
{command}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>EasyIDP</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Installing Python packages for EasyIDP</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Cancel</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Some tools need Python packages that QGIS's Python lacks: {packages}.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Install</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Download them with pip into your QGIS profile; QGIS's own packages are not changed.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Every Python package EasyIDP needs is installed.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Installing {packages} …</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Python packages installed: {packages}.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Restart QGIS to use them: an older copy is already loaded.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>nothing was missing</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Installation cancelled; nothing was changed. To install later, run:
{command}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Installing the Python packages failed: {reason}. Run this command in a terminal to see why:
{command}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>still missing after pip: {packages}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>exit status {code}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Project CRS (Pix4D without a *_wkt.prj file; OpenSfM without OpenDroneMap)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Point cloud (.las, .laz or .ply)</source>
      <translation>点云（.las、.laz 或 .ply）</translation>
    </message>
    <message>
      <source>Point cloud CRS (needed for PLY and for LAS without a CRS; otherwise read from the file)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Lowest Z to keep (cloud Z units; empty: no limit)</source>
      <translation>保留的最低 Z（点云 Z 单位；留空：不限制）</translation>
    </message>
    <message>
      <source>Highest Z to keep (cloud Z units; empty: no limit)</source>
      <translation>保留的最高 Z（点云 Z 单位；留空：不限制）</translation>
    </message>
    <message>
      <source>Photogrammetry project (Metashape .psx/.psz/.xml; Pix4D .p4d, project or params folder; OpenDroneMap folder or reconstruction.json)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Chunk: Metashape chunk (label or index) or OpenSfM reconstruction index (needed when there are several)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Photogrammetry project: none given ({what}).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{path}: the project's CRS is unknown (a Pix4D project without *_wkt.prj, or an OpenSfM dataset without GPS): set 'Project CRS'.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} camera(s) are not aligned and have no pose: {names}</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>'{a}' and '{b}' are both {path}: one would replace the other. Choose two files.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{output}: {path} already exists and nothing was written. Choose another file, or tick 'Overwrite existing files' (advanced) to replace it.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{output}: {path} is also the input '{input}'. Inputs are never overwritten: choose another file.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{name}: {value} is not a number; give a finite value.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{name}: {value:g} is outside the range {lo}–{hi}.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{name}: {value} is not one of the choices ({opts}).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>{n} files are more than the {limit} loaded into the map: open them from the output folder.</source>
      <translation type="unfinished" />
    </message>
  </context>
</TS>