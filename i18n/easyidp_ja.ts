<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="ja">
  <context>
    <name>EasyIDP</name>
    <message>
      <source>Camera positions and footprints</source>
      <translation>カメラ位置と撮影範囲</translation>
    </message>
    <message>
      <source>Photogrammetry projects</source>
      <translation>写真測量プロジェクト</translation>
    </message>
    <message>
      <source>Reads the solved cameras of an Agisoft Metashape project (.psx with its .files folder, .psz, or an exported cameras .xml) or a Pix4D project (.p4d, the project folder or its 1_initial/params folder: choose any file in it, e.g. *_pmatrix.txt) and draws, for every aligned camera, its position and the part of the ground its photo sees. Run it first to check that a project was read right.

The footprint is the photo border (densified, with the lens distortion) cast onto the DSM, or onto a constant ground height when no DSM is given. Attributes: label, photo path, enabled, height above ground (m), view angle from nadir (degrees), and for footprints the area (m²) and whether the whole border reached the ground.

Outputs are in the project CRS, or the output CRS if one is chosen. A Pix4D params folder without *_wkt.prj needs the project CRS. Heights of the DSM or the ground height must be in the project's vertical reference (for a Metashape chunk in a geographic CRS: ellipsoidal heights).</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Output CRS (default: the project CRS)</source>
      <translation>出力 CRS（既定：プロジェクトの CRS）</translation>
    </message>
    <message>
      <source>Photogrammetry project (Metashape .psx/.psz/.xml; Pix4D .p4d or a file of its params folder)</source>
      <translation>写真測量プロジェクト（Metashape .psx/.psz/.xml、Pix4D .p4d または params フォルダ内のファイル）</translation>
    </message>
    <message>
      <source>Metashape chunk (label or index; needed when there are several)</source>
      <translation>Metashape チャンク（名前または番号、複数ある場合は必須）</translation>
    </message>
    <message>
      <source>Project CRS (Pix4D projects without a *_wkt.prj file)</source>
      <translation>プロジェクト CRS（*_wkt.prj のない Pix4D プロジェクト用）</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF) for the footprints</source>
      <translation>撮影範囲用の DSM（GeoTIFF）</translation>
    </message>
    <message>
      <source>Ground height when no DSM is given (project vertical reference)</source>
      <translation>DSM がない場合の地面の高さ（プロジェクトの高さ基準）</translation>
    </message>
    <message>
      <source>Camera positions</source>
      <translation>カメラ位置</translation>
    </message>
    <message>
      <source>Camera footprints</source>
      <translation>撮影範囲</translation>
    </message>
    <message>
      <source>DSM</source>
      <translation>DSM</translation>
    </message>
    <message>
      <source>Give a DSM or a ground height: the footprints are where the photos meet the ground.</source>
      <translation>DSM または地面の高さを指定してください。撮影範囲は写真が地面と交わる範囲です。</translation>
    </message>
    <message>
      <source>Crop point cloud by ROIs</source>
      <translation>ROI で点群を切り出し</translation>
    </message>
    <message>
      <source>Cropping</source>
      <translation>切り出し</translation>
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
      <translation>点のない ROI にも空のファイルを書き出す</translation>
    </message>
    <message>
      <source>ROIs</source>
      <translation>ROI</translation>
    </message>
    <message>
      <source>ROIs (polygons)</source>
      <translation>ROI（ポリゴン）</translation>
    </message>
    <message>
      <source>Name field (default: feature id)</source>
      <translation>名前フィールド（既定：地物 ID）</translation>
    </message>
    <message>
      <source>Output format</source>
      <translation>出力形式</translation>
    </message>
    <message>
      <source>Output folder</source>
      <translation>出力フォルダ</translation>
    </message>
    <message>
      <source>Cropped point clouds</source>
      <translation>切り出した点群</translation>
    </message>
    <message>
      <source>Number of ROIs cropped</source>
      <translation>切り出した ROI の数</translation>
    </message>
    <message>
      <source>Number of ROIs without points</source>
      <translation>点のない ROI の数</translation>
    </message>
    <message>
      <source>Number of ROIs outside the cloud</source>
      <translation>点群の範囲外の ROI の数</translation>
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
      <translation>ROI でラスタを切り出し</translation>
    </message>
    <message>
      <source>Cuts every ROI (plot, tree, plant polygon) out of a GeoTIFF raster: an orthomosaic (DOM), a surface model (DSM) or a multispectral map, into one GeoTIFF per ROI in the output folder, named after the name field (made safe for file names and unique).

The raster is read in a single pass, each tile or strip once, so thousands of ROIs on rasters larger than memory are fast. Crops keep the raster's pixel grid, CRS and data type. Pixels outside the ROI are masked: RGB gets an alpha band, RGBA its alpha combined, DSM and multispectral get nodata (the raster's own, or -32767 for floating point and the type's extreme for integers when it has none). A pixel belongs to an ROI when its centre is inside (GDAL's rule); 'All touched' takes every pixel the ROI touches. Holes and multipart polygons are honoured. ROIs in another CRS are reprojected; ROIs outside the raster are reported and skipped.</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>All touched (include every pixel the ROI touches)</source>
      <translation>接触する全ピクセル（ROI に触れるすべてのピクセルを含める）</translation>
    </message>
    <message>
      <source>Raster</source>
      <translation>ラスタ</translation>
    </message>
    <message>
      <source>Raster (GeoTIFF: orthomosaic, DSM or multispectral)</source>
      <translation>ラスタ（GeoTIFF：オルソモザイク、DSM またはマルチスペクトル）</translation>
    </message>
    <message>
      <source>Cropped rasters</source>
      <translation>切り出したラスタ</translation>
    </message>
    <message>
      <source>Number of ROIs skipped</source>
      <translation>スキップした ROI の数</translation>
    </message>
    <message>
      <source>Point cloud statistics per ROI</source>
      <translation>ROI ごとの点群統計</translation>
    </message>
    <message>
      <source>Heights</source>
      <translation>高さ</translation>
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
      <translation>高さのパーセンタイル（カンマ区切り）</translation>
    </message>
    <message>
      <source>ROIs with point cloud statistics</source>
      <translation>点群統計付き ROI</translation>
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
      <translation>DSM から ROI の高さを取得</translation>
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
      <translation>頂点のサンプリング</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF)</source>
      <translation>DSM（GeoTIFF）</translation>
    </message>
    <message>
      <source>Mode</source>
      <translation>モード</translation>
    </message>
    <message>
      <source>Statistic</source>
      <translation>統計量</translation>
    </message>
    <message>
      <source>Percentile (for the 'percentile' statistic)</source>
      <translation>パーセンタイル（「percentile」統計量用）</translation>
    </message>
    <message>
      <source>Buffer (DSM map units; negative shrinks the polygon)</source>
      <translation>バッファ（DSM の地図単位、負の値でポリゴンを縮小）</translation>
    </message>
    <message>
      <source>ROIs with heights</source>
      <translation>高さ付き ROI</translation>
    </message>
    <message>
      <source>Point cloud (.las, .laz or .ply)</source>
      <translation>点群（.las、.laz または .ply）</translation>
    </message>
    <message>
      <source>Point cloud CRS (needed for PLY and for LAS without a CRS; otherwise read from the file)</source>
      <translation type="unfinished" />
    </message>
    <message>
      <source>Lowest Z to keep (cloud Z units; empty: no limit)</source>
      <translation>残す最低 Z（点群の Z 単位、空欄：制限なし）</translation>
    </message>
    <message>
      <source>Highest Z to keep (cloud Z units; empty: no limit)</source>
      <translation>残す最高 Z（点群の Z 単位、空欄：制限なし）</translation>
    </message>
  </context>
</TS>