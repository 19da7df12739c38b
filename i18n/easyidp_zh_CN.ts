<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="zh_CN">
  <context>
    <name>EasyIDP</name>
    <message>
      <source>Camera positions and footprints</source>
      <translation>相机位置与地面覆盖范围</translation>
    </message>
    <message>
      <source>Photogrammetry projects</source>
      <translation>摄影测量工程</translation>
    </message>
    <message>
      <source>Reads the solved cameras of an Agisoft Metashape project (.psx with its .files folder, .psz, or an exported cameras .xml) or a Pix4D project (.p4d, the project folder or its 1_initial/params folder: choose any file in it, e.g. *_pmatrix.txt) and draws, for every aligned camera, its position and the part of the ground its photo sees. Run it first to check that a project was read right.

The footprint is the photo border (densified, with the lens distortion) cast onto the DSM, or onto a constant ground height when no DSM is given. Attributes: label, photo path, enabled, height above ground (m), view angle from nadir (degrees), and for footprints the area (m²) and whether the whole border reached the ground.

Outputs are in the project CRS, or the output CRS if one is chosen. A Pix4D params folder without *_wkt.prj needs the project CRS. Heights of the DSM or the ground height must be in the project's vertical reference (for a Metashape chunk in a geographic CRS: ellipsoidal heights).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Output CRS (default: the project CRS)</source>
      <translation>输出坐标系（默认：工程坐标系）</translation>
    </message>
    <message>
      <source>Photogrammetry project (Metashape .psx/.psz/.xml; Pix4D .p4d or a file of its params folder)</source>
      <translation>摄影测量工程（Metashape .psx/.psz/.xml；Pix4D .p4d 或其 params 文件夹中的文件）</translation>
    </message>
    <message>
      <source>Metashape chunk (label or index; needed when there are several)</source>
      <translation>Metashape 块（名称或序号；有多个块时必填）</translation>
    </message>
    <message>
      <source>Project CRS (Pix4D projects without a *_wkt.prj file)</source>
      <translation>工程坐标系（用于没有 *_wkt.prj 文件的 Pix4D 工程）</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF) for the footprints</source>
      <translation>用于覆盖范围的 DSM（GeoTIFF）</translation>
    </message>
    <message>
      <source>Ground height when no DSM is given (project vertical reference)</source>
      <translation>未提供 DSM 时的地面高度（工程高程基准）</translation>
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
      <source>DSM</source>
      <translation>DSM</translation>
    </message>
    <message>
      <source>Give a DSM or a ground height: the footprints are where the photos meet the ground.</source>
      <translation>请提供 DSM 或地面高度：覆盖范围是照片与地面相交之处。</translation>
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
      <source>Write empty files for ROIs without any point</source>
      <translation>为没有点的感兴趣区写出空文件</translation>
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
      <source>Output format</source>
      <translation>输出格式</translation>
    </message>
    <message>
      <source>Output folder</source>
      <translation>输出文件夹</translation>
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
      <source>Crop raster by ROIs</source>
      <translation>按感兴趣区裁剪栅格</translation>
    </message>
    <message>
      <source>Cuts every ROI (plot, tree, plant polygon) out of a GeoTIFF raster: an orthomosaic (DOM), a surface model (DSM) or a multispectral map, into one GeoTIFF per ROI in the output folder, named after the name field (made safe for file names and unique).

The raster is read in a single pass, each tile or strip once, so thousands of ROIs on rasters larger than memory are fast. Crops keep the raster's pixel grid, CRS and data type. Pixels outside the ROI are masked: RGB gets an alpha band, RGBA its alpha combined, DSM and multispectral get nodata (the raster's own, or -32767 for floating point and the type's extreme for integers when it has none). A pixel belongs to an ROI when its centre is inside (GDAL's rule); 'All touched' takes every pixel the ROI touches. Holes and multipart polygons are honoured. ROIs in another CRS are reprojected; ROIs outside the raster are reported and skipped.</source>
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
      <source>Ground without raster or height: this percentile of each ROI's Z</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: DSM/DTM raster (GeoTIFF; optional)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Ground: one height for all ROIs (cloud Z units; optional)</source>
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
      <source>ROI heights from DSM</source>
      <translation>从 DSM 获取感兴趣区高度</translation>
    </message>
    <message>
      <source>Gives every ROI its height from a surface model (DSM), as the Z of its vertices and as the attribute 'height' (in the DSM's units and vertical reference). The result is the ROI layer as PolygonZ, ready for backward projection into raw photos.

Per polygon: the statistic (mean, median, min, max or a percentile, e.g. 90 for canopy top, 5 for ground) of the DSM pixels whose centres are inside the ROI, grown by a positive buffer or shrunk by a negative one (map units of the DSM). Every vertex gets that height.
Per vertex: the DSM height at each vertex (bilinear or nearest pixel), or, with a buffer, the statistic of the pixels within the buffer distance of the vertex; 'height' is then the mean of the vertex heights.

Nodata pixels are ignored. An ROI without any valid pixel keeps an empty (NULL) height and NaN Z, and is listed in the log; it never gets 0.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Vertex sampling</source>
      <translation>顶点采样</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF)</source>
      <translation>数字表面模型 DSM（GeoTIFF）</translation>
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
      <source>Percentile (for the 'percentile' statistic)</source>
      <translation>百分位数（用于“percentile”统计量）</translation>
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
  </context>
</TS>