<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="zh_CN">
  <context>
    <name>EasyIDP</name>
    <message>
      <source>Back-project ROIs</source>
      <translation>将感兴趣区反投影到原始照片</translation>
    </message>
    <message>
      <source>Projection</source>
      <translation>投影</translation>
    </message>
    <message>
      <source>Finds every ROI (plot, tree, plant polygon) in every raw photo of a Metashape or Pix4D project that sees it, using the cameras the project solved (EasyIDP's back2raw). Raw photos are sharper than the orthomosaic and free of its seamlines.

Inputs: the ROI polygons; the project (Metashape .psx/.psz/cameras .xml, Pix4D .p4d or any file of its 1_initial/params folder, or a folder of drone photos whose EXIF and XMP tags give rough cameras: each pixel feature then carries its expected error, uncertainty_px); the height of the ROI vertices, from the geometry's Z (e.g. the output of ROI heights from DSM), a DSM sampled at every vertex, a numeric attribute, or one ground height (heights in the project's vertical reference; for a Metashape chunk in a geographic CRS: ellipsoidal). Photos folder: where the photos are when they moved (matched by file name).

Each ROI is densified, projected with the lens distortion, and clipped to the photo frame (or, with 'whole ROIs only', kept only where the whole ROI is in the photo). With a DSM, lines of sight to points on the surface inside the ROI are tested for occlusion. Photos showing less than the minimum visible, unoccluded share are dropped; the others are ranked by a score (view angle, ground resolution, distance from the photo centre, visible share).

Outputs: the ROIs in photo pixels (x = column, y = −row: they lie on a raw photo opened in QGIS without georeference; filter by 'photo'), one feature per ROI × photo with score, rank, view angle, GSD and fractions; a summary of the ROIs in the map with their photo count and best photo; optionally EasyIDP's JSON {roi: {photo: [[x, y], ...]}}, the crops of the raw photos (PNG with the ROI as alpha, TIFF for 16-bit or multiband photos, each with a JSON sidecar) and one preview PNG per ROI showing its best photos.

Values of the crops: as stored (the photos' own pixels, the default), temperature in °C (FLIR radiometric JPEGs by the Planck curve, with the photo's object parameters unless given; temperature TIFFs by their preset or scale and offset) or reflectance (MicaSense and DJI multispectral band files), as in Plot statistics from photos. Temperature and reflectance crops are float32 TIFFs with the unit and what was applied in their GDAL metadata; saturated or unreadable pixels are NaN (nodata). A photo that holds no such values is skipped with why.</source>
      <translation>在 Metashape 或 Pix4D 工程中，利用工程解算出的相机，找出每个感兴趣区（小区、树木、植株多边形）在所有能看到它的原始照片中的位置（EasyIDP 的 back2raw）。原始照片比正射影像更清晰，且没有拼接线。

输入：感兴趣区多边形；工程（Metashape .psx/.psz/相机 .xml，Pix4D .p4d 或其 1_initial/params 文件夹中的任一文件，或一个无人机照片文件夹：由照片的 EXIF 和 XMP 标签得到粗略的相机，此时每个像素要素带有其预期误差 uncertainty_px）；感兴趣区顶点的高度，可来自几何的 Z 值（如“从 DSM 获取感兴趣区高度”的输出）、在每个顶点采样的 DSM、数值属性或单一地面高度（高度采用工程的高程基准；对于地理坐标系中的 Metashape 块（chunk）：椭球高）。照片文件夹：照片被移动后所在的位置（按文件名匹配）。

每个感兴趣区先加密顶点，再结合镜头畸变进行投影，并裁剪到照片画幅内（若选择“仅限完整感兴趣区”，则只在整个感兴趣区都位于照片内时保留）。提供 DSM 时，会检测从相机到感兴趣区内地表点的视线是否被遮挡。可见且未被遮挡的比例低于最小值的照片会被舍弃；其余照片按评分排序（视角、地面分辨率、到照片中心的距离、可见比例）。

输出：照片像素坐标下的感兴趣区（x = 列，y = −行：可叠加在 QGIS 中未经地理配准打开的原始照片上；按 photo 字段筛选），每个感兴趣区 × 照片一个要素，含评分、排名、视角、地面采样距离（GSD）及各比例；地图中感兴趣区的汇总，含照片数量和最佳照片；可选输出 EasyIDP 的 JSON {roi: {photo: [[x, y], ...]}}、原始照片的裁剪图（PNG，以感兴趣区作为 alpha 通道；16 位或多波段照片为 TIFF，均附带 JSON 附属文件），以及每个感兴趣区一张展示其最佳照片的预览 PNG。

裁剪图的数值：按存储的值（照片自身的像素，默认）、以 °C 表示的温度（FLIR 辐射测量 JPEG 按普朗克曲线换算，未给出时使用照片自带的目标参数；温度 TIFF 按其预设或比例与偏移换算）或反射率（MicaSense 与大疆多光谱波段文件），与“原始照片的小区统计”相同。温度和反射率的裁剪图为 float32 TIFF，其 GDAL 元数据中注明单位及所做的换算；饱和或无法读取的像素为 NaN（无数据）。不含此类数值的照片会被跳过并说明原因。</translation>
    </message>
    <message>
      <source>Only this photo</source>
      <translation>仅此照片</translation>
    </message>
    <message>
      <source>Its file name or camera label; empty: every photo</source>
      <translation>其文件名或相机标签；留空：所有照片</translation>
    </message>
    <message>
      <source>Apply the lens distortion (off for undistorted photos)</source>
      <translation>应用镜头畸变（对已去畸变的照片请关闭）</translation>
    </message>
    <message>
      <source>Margin around the crops (pixels)</source>
      <translation>裁剪图四周的边距（像素）</translation>
    </message>
    <message>
      <source>Values of the crops</source>
      <translation>裁剪图的数值</translation>
    </message>
    <message>
      <source>photos</source>
      <translation>张照片</translation>
    </message>
    <message>
      <source>Photos folder (when the photos moved; matched by file name)</source>
      <translation>照片文件夹（照片被移动时使用；按文件名匹配）</translation>
    </message>
    <message>
      <source>ROIs partly outside a photo</source>
      <translation>部分位于照片外的感兴趣区</translation>
    </message>
    <message>
      <source>Test occlusion against the DSM (when a DSM is given)</source>
      <translation>基于 DSM 检测遮挡（提供 DSM 时）</translation>
    </message>
    <message>
      <source>Minimum visible, unoccluded share of a ROI in a photo</source>
      <translation>感兴趣区在照片中可见且未被遮挡的最小比例</translation>
    </message>
    <message>
      <source>Best photos to keep per ROI (0 = all)</source>
      <translation>每个感兴趣区保留的最佳照片数（0 = 全部）</translation>
    </message>
    <message>
      <source>ROIs in photo pixels (x = column, y = −row)</source>
      <translation>照片像素坐标下的感兴趣区（x = 列，y = −行）</translation>
    </message>
    <message>
      <source>ROIs with their photo count and best photo</source>
      <translation>带照片数量和最佳照片的感兴趣区</translation>
    </message>
    <message>
      <source>EasyIDP back2raw JSON</source>
      <translation>EasyIDP back2raw JSON</translation>
    </message>
    <message>
      <source>Crops of the raw photos</source>
      <translation>原始照片裁剪图</translation>
    </message>
    <message>
      <source>Preview per ROI (its best photos)</source>
      <translation>每个感兴趣区的预览（其最佳照片）</translation>
    </message>
    <message>
      <source>No DSM given: occlusion is not tested.</source>
      <translation>未提供 DSM：不检测遮挡。</translation>
    </message>
    <message>
      <source>The values chosen apply to the crops and previews only, and neither folder was given.</source>
      <translation>所选的数值只用于裁剪图和预览，但两个文件夹都没有给出。</translation>
    </message>
    <message>
      <source>Cutting the ROIs out of the photos…</source>
      <translation>正在从照片中裁出感兴趣区…</translation>
    </message>
    <message>
      <source>The ROIs in photo pixels open in the EasyIDP photo viewer (toolbar), over their photos, not in the map.</source>
      <translation>照片像素中的 ROI 在 EasyIDP 照片查看器（工具栏）中叠加在其照片上打开，而不是在地图中。</translation>
    </message>
    <message>
      <source>Clip them to the photo frame</source>
      <translation>裁剪到照片画幅内</translation>
    </message>
    <message>
      <source>Drop the photo (whole ROIs only)</source>
      <translation>舍弃该照片（仅限完整感兴趣区）</translation>
    </message>
    <message>
      <source>Projecting {n} ROIs into {m} photos ({h})</source>
      <translation>正在将 {n} 个感兴趣区投影到 {m} 张照片中（{h}）</translation>
    </message>
    <message>
      <source>{rois} in the photos of {project} (photo pixels)</source>
      <translation>{project} 照片中的 {rois}（照片像素）</translation>
    </message>
    <message>
      <source>{rois}: photos of {project} that see them</source>
      <translation>{rois}：{project} 中能看到它们的照片</translation>
    </message>
    <message>
      <source>{k} ROI × photo pairs for {seen} of {n} ROIs; {u} ROIs in no photo.</source>
      <translation>{n} 个感兴趣区中的 {seen} 个共得到 {k} 个感兴趣区 × 照片组合；{u} 个感兴趣区不在任何照片中。</translation>
    </message>
    <message>
      <source>ROI '{name}': {why}</source>
      <translation>感兴趣区“{name}”：{why}</translation>
    </message>
    <message>
      <source>… and {n} more ROIs without a photo</source>
      <translation>… 以及另外 {n} 个没有照片的感兴趣区</translation>
    </message>
    <message>
      <source>{n} crops and {p} previews written.</source>
      <translation>已写出 {n} 张裁剪图和 {p} 张预览图。</translation>
    </message>
    <message>
      <source>Photo {label} skipped: {why}</source>
      <translation>已跳过照片 {label}：{why}</translation>
    </message>
    <message>
      <source>Overwrite existing files</source>
      <translation>覆盖已有文件</translation>
    </message>
    <message>
      <source>Otherwise the tool stops before writing anything when an output already exists</source>
      <translation>否则，当输出已存在时，工具在写入任何内容之前停止</translation>
    </message>
    <message>
      <source>Cameras and footprints</source>
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
      <translation>读取 Agisoft Metashape 工程（.psx 及其 .files 文件夹、.psz 或导出的相机 .xml）、Pix4D 工程（.p4d、工程文件夹或其 1_initial/params 文件夹：选择其中任一文件，如 *_pmatrix.txt）或 OpenDroneMap/OpenSfM 工程（选择 ODM 工程文件夹中的 opensfm/reconstruction.json；Python 脚本可直接给出该文件夹）中解算出的相机，并为每台已对齐的相机绘制其位置及其照片所见的地面范围。请先运行此工具，以检查工程是否被正确读取。

块（chunk）：Metashape 的块（标签或索引），或 OpenSfM 重建（部分模型的索引；默认为最大的一个，见日志）。

覆盖范围是照片边框（加密顶点并考虑镜头畸变）投射到 DSM 上的结果；未提供 DSM 时，则投射到固定地面高度上。属性：标签、照片路径、是否启用、离地高度（m）、偏离天底的视角（度），覆盖范围另有面积（m²）以及整个边框是否都落在地面数据上（complete；在 DSM 结束处，覆盖范围在相机正下方地面高度的平面上延续）。位于地面或地面以下的相机没有覆盖范围，并会在日志中列出。

带卷帘快门补偿的 Metashape 工程：每张照片的每个图像行各有一个位姿（Metashape 估计的读出期间的运动）；覆盖范围与所有投影一样会使用它，日志会说明何时应用。

如果选择了输出坐标系，则输出采用该坐标系，否则依次采用 DSM 的坐标系、地图的坐标系、摄影测量工程的坐标系（日志会说明采用哪个）。没有 *_wkt.prj 的 Pix4D params 文件夹需要设置工程坐标系。ODM 工程采用 ODM 的坐标系（即其正射影像和 DSM 的坐标系）；没有 ODM 的 OpenSfM 数据集使用其参考点所在的 WGS 84 / UTM 带，除非设置了工程坐标系。DSM 的高度或地面高度必须采用工程的高程基准（对于地理坐标系中的 Metashape 块：椭球高；对于 ODM：其 DSM 的高度）。</translation>
    </message>
    <message>
      <source>Output CRS</source>
      <translation>输出坐标参考系</translation>
    </message>
    <message>
      <source>Default: the DSM's, else the map's, else the photogrammetry project's</source>
      <translation>默认：DSM 的，否则为地图的，否则为摄影测量项目的</translation>
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
      <translation>所选的输出坐标系</translation>
    </message>
    <message>
      <source>the DSM's CRS</source>
      <translation>DSM 的坐标系</translation>
    </message>
    <message>
      <source>the map's CRS</source>
      <translation>地图的坐标系</translation>
    </message>
    <message>
      <source>{n} camera(s) have no DSM right under them: their height above ground is taken from the DSM where their photo sees the ground.</source>
      <translation>{n} 台相机正下方没有 DSM：其离地高度取自其照片所见地面处的 DSM。</translation>
    </message>
    <message>
      <source>{n} camera(s) see no DSM at all: their height above ground is taken from the median ground under the other cameras.</source>
      <translation>{n} 台相机完全看不到 DSM：其离地高度取其他相机下方地面高度的中位数。</translation>
    </message>
    <message>
      <source>Ground height when no DSM is given</source>
      <translation>未提供 DSM 时的地面高度</translation>
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
      <source>Camera footprints of {project}</source>
      <translation>{project} 的相机地面覆盖范围</translation>
    </message>
    <message>
      <source>Cameras of {project}</source>
      <translation>{project} 的相机</translation>
    </message>
    <message>
      <source>Outputs in {crs} (the photogrammetry project's CRS).</source>
      <translation>输出采用 {crs}（摄影测量工程的坐标系）。</translation>
    </message>
    <message>
      <source>{n} cameras and {f} footprints written.</source>
      <translation>已写出 {n} 台相机和 {f} 个覆盖范围。</translation>
    </message>
    <message>
      <source>The project is in a local coordinate system ({name}): the outputs will not line up with map layers.</source>
      <translation>工程位于局部坐标系（{name}）中：输出将无法与地图图层对齐。</translation>
    </message>
    <message>
      <source>{n} camera(s) are at or below the ground, so they have no footprint: {names}. Check the ground height or the DSM and its vertical reference.</source>
      <translation>{n} 台相机位于地面或地面以下，因此没有覆盖范围：{names}。请检查地面高度，或 DSM 及其高程基准。</translation>
    </message>
    <message>
      <source>{n} footprint(s) reach beyond the DSM's data: there they continue on a plane at the ground height under the camera (attribute complete = false).</source>
      <translation>{n} 个覆盖范围超出了 DSM 的数据范围：超出部分在相机下方地面高度的平面上延续（属性 complete = false）。</translation>
    </message>
    <message>
      <source>Outputs in {crs} ({why}).</source>
      <translation>输出采用 {crs}（{why}）。</translation>
    </message>
    <message>
      <source>Create demo survey</source>
      <translation>创建演示航测数据</translation>
    </message>
    <message>
      <source>Demo data</source>
      <translation>演示数据</translation>
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

Field (advanced): messy (default) gives the field what real ones have: grass in the margins, weeds in and between the plots, uneven vigour, missing row segments, empty and lodged plots, shadows, a soil-colour gradient, rows tall and full enough to hide the soil between them in oblique views, and one block of plots without alleys. Tidy gives the field of earlier versions: narrow rows on bare soil, nothing else.

Growth season (advanced): with N dates, also the same field flown on N dates while the crop grows along known curves, in season/: per date an orthomosaic, a DSM and a point cloud, a bare-soil DSM, the plots with their variety, surveys.csv (the table for 'Plot traits over a season') and season_truth.json (height and cover per plot and date).</source>
      <translation>写出一套小型、完整且真值已知的合成无人机航测数据，无需下载任何内容即可立即试用 EasyIDP 的所有工具。航测区域为 60 m × 40 m 的田块，含 40 个小区（UTM 54N）：
- 正射影像（1 cm）、DSM（2 cm）和小区（GeoPackage 和 GeoJSON，字段 plot_id）；
- 彩色点云（LAZ 和 PLY）；
- 弓字形航线拍摄的 36 张原始照片，通过相机模型渲染；
- 同一次飞行的 Agisoft Metashape 工程、Pix4D 工程和 OpenDroneMap 工程（odm/，含其 opensfm/ 文件）；
- 四张照片上的 LabelMe 标注；
- truth.json：已知地面点在每张照片中的位置。

相同的随机种子生成相同的文件。“小”只需几秒；“中”的照片更大。

田块（高级）：杂乱（默认）给田块以真实田块的一切：边缘的草、小区内外的杂草、长势不均、缺行段、空小区和倒伏小区、阴影、土壤颜色渐变、高而密到斜视时遮住行间土壤的作物行，以及一组没有走道的小区。整齐即早期版本的田块：裸土上的窄行，别无其他。

生长季（高级）：设置 N 个日期时，还会在 season/ 中生成同一田块在 N 个日期飞行的数据，作物按已知曲线生长：每个日期的正射影像、DSM 和点云，一个裸土 DSM，带品种信息的小区，surveys.csv（“生长季小区性状”所用的表）和 season_truth.json（每个小区和日期的高度与覆盖度）。</translation>
    </message>
    <message>
      <source>Random seed</source>
      <translation>随机种子</translation>
    </message>
    <message>
      <source>Field</source>
      <translation>田块</translation>
    </message>
    <message>
      <source>Growth season: dates flown (0: none)</source>
      <translation>生长季：飞行日期数（0：无）</translation>
    </message>
    <message>
      <source>Output folder</source>
      <translation>输出文件夹</translation>
    </message>
    <message>
      <source>Size</source>
      <translation>尺寸</translation>
    </message>
    <message>
      <source>Season survey table (surveys.csv)</source>
      <translation>生长季航测表（surveys.csv）</translation>
    </message>
    <message>
      <source>Orthomosaic</source>
      <translation>正射影像</translation>
    </message>
    <message>
      <source>Plots</source>
      <translation>小区</translation>
    </message>
    <message>
      <source>Point cloud (LAZ)</source>
      <translation>点云（LAZ）</translation>
    </message>
    <message>
      <source>Metashape project</source>
      <translation>Metashape 工程</translation>
    </message>
    <message>
      <source>Pix4D project</source>
      <translation>Pix4D 工程</translation>
    </message>
    <message>
      <source>OpenDroneMap project</source>
      <translation>OpenDroneMap 工程</translation>
    </message>
    <message>
      <source>OPF project (project.opf, PIX4Dmatic)</source>
      <translation>OPF 工程（project.opf，PIX4Dmatic）</translation>
    </message>
    <message>
      <source>Truth file</source>
      <translation>真值文件</translation>
    </message>
    <message>
      <source>Demo survey</source>
      <translation>演示航测数据</translation>
    </message>
    <message>
      <source>messy (weeds, margin grass, tall rows, gaps, …)</source>
      <translation>杂乱（杂草、边缘草、高作物行、缺行…）</translation>
    </message>
    <message>
      <source>tidy (narrow rows on bare soil)</source>
      <translation>整齐（裸土上的窄行）</translation>
    </message>
    <message>
      <source>Writing a {size} demo survey (seed {seed}, {field} field) into {folder}</source>
      <translation>正在将 {size} 演示航测数据（随机种子 {seed}，{field} 田块）写入 {folder}</translation>
    </message>
    <message>
      <source>Demo survey written in {seconds:.1f} s: {n_photos} photos, {n_plot_ids} plots, {dates} season dates, in {folder}.</source>
      <translation>演示航测数据已在 {seconds:.1f} s 内写入 {folder}：{n_photos} 张照片，{n_plot_ids} 个小区，{dates} 个生长季日期。</translation>
    </message>
    <message>
      <source>small (800 × 600 photos)</source>
      <translation>小（800 × 600 照片）</translation>
    </message>
    <message>
      <source>medium (1600 × 1200 photos)</source>
      <translation>中（1600 × 1200 照片）</translation>
    </message>
    <message>
      <source>Demo plots</source>
      <translation>演示小区</translation>
    </message>
    <message>
      <source>Demo orthomosaic</source>
      <translation>演示正射影像</translation>
    </message>
    <message>
      <source>Demo DSM</source>
      <translation>演示 DSM</translation>
    </message>
    <message>
      <source>Growth season: {n} dates in {f}</source>
      <translation>生长季：{n} 个日期，位于 {f}</translation>
    </message>
    <message>
      <source>Create plot grid</source>
      <translation>创建地块网格</translation>
    </message>
    <message>
      <source>ROIs</source>
      <translation>感兴趣区</translation>
    </message>
    <message>
      <source>Makes the plot polygons of a trial from its field layout: rows (ranges) × columns (passes) of plots, in blocks, numbered and joined to the field book.

Anchor: four corner points of the field in any order (they are sorted clockwise from the upper-left corner, the one whose edge to the next points closest to east; the log says the order used), a field-boundary polygon (its minimum-area rectangle), or an origin (the upper-left corner) and the bearing of the top edge (90 = east). Columns are counted along the top edge (x), rows down the left edge (y).

Layout, per axis: plot size, gap between plots (or the spacing, centre to centre), blocks and the gap between blocks. With corners or a boundary, a size or gap left empty is solved so that the plots fill the field. A negative buffer shrinks every plot on each side (a positive one grows it); plots stay rectangles.

Numbering: row by row, column by column or serpentine, from any corner, from the start id; the name pattern takes {plot_no}, {row}, {col}, {block}, {block_row}, {block_col}, {row_letter}, {range} and {pass}, e.g. {block}-{row:02d}-{col:02d}.

Field book: a table (e.g. a CSV layer) joined by plot id, plot number, or row and column; rows that match no plot and plots without a row are listed in the log.

The CRS must be projected in metres: a geographic CRS is refused with the UTM zone to use. Corners that are not a rectangle, and plots that would overlap, are refused with the amount.</source>
      <translation>根据田间布局生成试验的地块多边形：按区组排列的行（range）× 列（pass）地块，编号并连接田间记录本。

锚定：田块的四个角点，顺序任意（从左上角开始按顺时针排序，左上角即其到下一个角点的边最接近正东方向的角；日志会给出所用的顺序）；田块边界多边形（取其最小面积外接矩形）；或原点（左上角）与上边的方位角（90 = 正东）。列沿上边（x）计数，行沿左边向下（y）计数。

布局（每个轴）：地块尺寸、地块间距（或中心到中心的间隔）、区组数及区组间距。使用角点或边界时，留空的尺寸或间距会被求解，使地块铺满田块。负的缓冲距离使每个地块各边内缩（正值则外扩）；地块保持为矩形。

编号：逐行、逐列或蛇形，可从任一角开始，从起始编号开始；名称模板可用 {plot_no}、{row}、{col}、{block}、{block_row}、{block_col}、{row_letter}、{range} 和 {pass}，例如 {block}-{row:02d}-{col:02d}。

田间记录本：一个表（例如 CSV 图层），按地块 ID、地块编号或行列连接；不匹配任何地块的记录行和没有记录行的地块会在日志中列出。

坐标参考系必须是以米为单位的投影坐标系：地理坐标系会被拒绝，并提示应使用的 UTM 带。不构成矩形的角点以及会重叠的地块会被拒绝，并给出偏差量。</translation>
    </message>
    <message>
      <source>Four corner points (any order)</source>
      <translation>四个角点（顺序任意）</translation>
    </message>
    <message>
      <source>Field boundary polygon (its minimum-area rectangle)</source>
      <translation>田块边界多边形（其最小面积外接矩形）</translation>
    </message>
    <message>
      <source>Origin point (upper-left corner) and bearing</source>
      <translation>原点（左上角）与方位角</translation>
    </message>
    <message>
      <source>Row by row</source>
      <translation>逐行</translation>
    </message>
    <message>
      <source>Serpentine rows (back and forth)</source>
      <translation>蛇形行（往返）</translation>
    </message>
    <message>
      <source>Column by column</source>
      <translation>逐列</translation>
    </message>
    <message>
      <source>Serpentine columns</source>
      <translation>蛇形列</translation>
    </message>
    <message>
      <source>Top left</source>
      <translation>左上</translation>
    </message>
    <message>
      <source>Top right</source>
      <translation>右上</translation>
    </message>
    <message>
      <source>Bottom left</source>
      <translation>左下</translation>
    </message>
    <message>
      <source>Bottom right</source>
      <translation>右下</translation>
    </message>
    <message>
      <source>Plot id (the name)</source>
      <translation>地块 ID（名称）</translation>
    </message>
    <message>
      <source>Plot number</source>
      <translation>地块编号</translation>
    </message>
    <message>
      <source>Row and column</source>
      <translation>行和列</translation>
    </message>
    <message>
      <source>How far the given corners may be from a rectangle</source>
      <translation>给定角点与矩形之间允许的最大偏差</translation>
    </message>
    <message>
      <source>Anchor</source>
      <translation>锚定</translation>
    </message>
    <message>
      <source>Field corners (4 points)</source>
      <translation>田块角点（4 个点）</translation>
    </message>
    <message>
      <source>Field boundary (a polygon)</source>
      <translation>田块边界（多边形）</translation>
    </message>
    <message>
      <source>Origin (upper-left corner of the field)</source>
      <translation>原点（田块左上角）</translation>
    </message>
    <message>
      <source>Rows (ranges)</source>
      <translation>行数（range）</translation>
    </message>
    <message>
      <source>Columns (passes)</source>
      <translation>列数（pass）</translation>
    </message>
    <message>
      <source>Plot size along a row (m; empty: fill the field)</source>
      <translation>沿行方向的地块尺寸（米；留空：铺满田块）</translation>
    </message>
    <message>
      <source>Plot size down a column (m; empty: fill the field)</source>
      <translation>沿列方向的地块尺寸（米；留空：铺满田块）</translation>
    </message>
    <message>
      <source>Gap between columns of plots (m; empty: solved)</source>
      <translation>地块列之间的间距（米；留空：求解）</translation>
    </message>
    <message>
      <source>Alley between rows of plots (m; empty: solved)</source>
      <translation>地块行之间的走道（米；留空：求解）</translation>
    </message>
    <message>
      <source>Column spacing, centre to centre (m; not the gap)</source>
      <translation>列间距，中心到中心（米；不是间隔）</translation>
    </message>
    <message>
      <source>Row spacing, centre to centre (m; not the alley)</source>
      <translation>行间距，中心到中心（米；不是走道）</translation>
    </message>
    <message>
      <source>Blocks along a row</source>
      <translation>沿行方向的区组数</translation>
    </message>
    <message>
      <source>Blocks down a column</source>
      <translation>沿列方向的区组数</translation>
    </message>
    <message>
      <source>Gap between blocks along a row (m; empty: the plot gap)</source>
      <translation>沿行方向的区组间距（米；留空：地块间距）</translation>
    </message>
    <message>
      <source>Gap between blocks down a column (m; empty: the alley)</source>
      <translation>沿列方向的区组间距（米；留空：走道）</translation>
    </message>
    <message>
      <source>Numbering order</source>
      <translation>编号顺序</translation>
    </message>
    <message>
      <source>Numbering starts at</source>
      <translation>编号起点</translation>
    </message>
    <message>
      <source>Start id (first plot number)</source>
      <translation>起始编号（第一个地块的编号）</translation>
    </message>
    <message>
      <source>Name pattern</source>
      <translation>名称模板</translation>
    </message>
    <message>
      <source>Field book (a table, e.g. a CSV layer)</source>
      <translation>田间记录本（一个表，例如 CSV 图层）</translation>
    </message>
    <message>
      <source>Join the field book by</source>
      <translation>田间记录本的连接依据</translation>
    </message>
    <message>
      <source>Field-book column of the plot id or number</source>
      <translation>田间记录表中小区编号或序号的列</translation>
    </message>
    <message>
      <source>Field-book column of the row (default: row)</source>
      <translation>田间记录本中行的列（默认：row）</translation>
    </message>
    <message>
      <source>Field-book column of the column (default: col)</source>
      <translation>田间记录本中列号的列（默认：col）</translation>
    </message>
    <message>
      <source>Corner tolerance (m)</source>
      <translation>角点容差（米）</translation>
    </message>
    <message>
      <source>Output CRS (projected, in metres; default: the anchor's)</source>
      <translation>输出坐标参考系（投影坐标系，单位为米；默认：锚定的坐标系）</translation>
    </message>
    <message>
      <source>Plot grid</source>
      <translation>地块网格</translation>
    </message>
    <message>
      <source>Bearing of the top edge (degrees clockwise from north)</source>
      <translation>上边的方位角（从北顺时针的度数）</translation>
    </message>
    <message>
      <source>Buffer (m; negative shrinks every plot on each side)</source>
      <translation>缓冲距离（米；负值使每个地块各边内缩）</translation>
    </message>
    <message>
      <source>Origin: give the upper-left corner of the field (or choose another anchor).</source>
      <translation>原点：请给出田块的左上角（或选择其他锚定方式）。</translation>
    </message>
    <message>
      <source>Plot grid {rows} × {cols}</source>
      <translation>地块网格 {rows} × {cols}</translation>
    </message>
    <message>
      <source>{n} plots in {crs}.</source>
      <translation>{n} 个地块，坐标系 {crs}。</translation>
    </message>
    <message>
      <source>Field corners: give a point layer with the four corners of the field (or choose another anchor).</source>
      <translation>田块角点：请给出含田块四个角点的点图层（或选择其他锚定方式）。</translation>
    </message>
    <message>
      <source>Field boundary: give a polygon layer with the field's outline (or choose another anchor).</source>
      <translation>田块边界：请给出含田块轮廓的多边形图层（或选择其他锚定方式）。</translation>
    </message>
    <message>
      <source>Field book '{name}': {n} columns joined ({fields}).</source>
      <translation>田间记录本“{name}”：连接了 {n} 列（{fields}）。</translation>
    </message>
    <message>
      <source>Field corners: the layer '{layer}' has {n} points; exactly four are needed, one per corner of the field.</source>
      <translation>田块角点：图层“{layer}”有 {n} 个点；需要恰好四个，每个角一个。</translation>
    </message>
    <message>
      <source>Field boundary: the layer '{layer}' has no polygon.</source>
      <translation>田块边界：图层“{layer}”没有多边形。</translation>
    </message>
    <message>
      <source>Origin '{value}' has no CRS: type it with its CRS in square brackets, e.g. '320000.0,3956100.0 [EPSG:32654]', or set the output CRS (the origin is then taken in it).</source>
      <translation>原点 '{value}' 没有坐标参考系：请在方括号中写上其坐标参考系，例如 '320000.0,3956100.0 [EPSG:32654]'，或设置输出坐标参考系（原点即按其解释）。</translation>
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
      <translation>将每个感兴趣区（小区、树木、植株多边形）从点云（.las、.laz 或 .ply，如 Pix4D 或 Metashape 的密集点云）中裁出，在输出文件夹中为每个感兴趣区生成一个文件，以名称字段命名（转换为可用作文件名的唯一名称）。

当点的 x、y 位于多边形内（考虑孔洞和多部件多边形），且（如已设置）其 Z 在 Z 范围内时（高级：例如去除地面以下或冠层以上的噪点），该点属于此感兴趣区。位于重叠感兴趣区内的点会分配给其中每一个。点云只读取一次，且每个点只与其附近的感兴趣区比较，因此在大型点云上处理数千个感兴趣区也很快。

保留所有点属性（颜色、强度、分类、回波、GPS 时间、法向量、额外维度）及精确坐标。LAS/LAZ 文件自带坐标系；PLY 文件没有，因此需要为其设置“点云坐标系”（没有坐标系的 LAS 文件也一样）。其他坐标系中的感兴趣区会重投影到点云的坐标系。

点云范围外的感兴趣区会在日志中列出并跳过；位于点云上但没有任何点的感兴趣区会被报告，除非勾选“写出空文件”，否则不生成文件。若此 QGIS 能显示点云（PDAL 数据提供程序），裁剪得到的 LAS/LAZ 文件会加载到地图中。</translation>
    </message>
    <message>
      <source>Same as input</source>
      <translation>与输入相同</translation>
    </message>
    <message>
      <source>LAZ (compressed LAS)</source>
      <translation>LAZ（压缩的 LAS）</translation>
    </message>
    <message>
      <source>Index of the crops (optional): the ROIs with the file ('crop_file'), the number of points ('points') and the outcome ('crop_status') of each. 'Open the crops in the map too' (off by default) opens up to 100 LAS/LAZ crops in one collapsed group below the ROI layer, where this QGIS can display point clouds (PDAL provider); a larger run opens the index only.</source>
      <translation>裁剪索引（可选）：各感兴趣区及其文件（'crop_file'）、点数（'points'）和结果（'crop_status'）。勾选“同时在地图中打开裁剪结果”（默认关闭）时，若此 QGIS 能显示点云（PDAL 提供程序），最多 100 个 LAS/LAZ 裁剪结果会在感兴趣区图层下方的一个折叠组中打开；更大的运行只打开索引。</translation>
    </message>
    <message>
      <source>Write empty files for ROIs without any point</source>
      <translation>为没有点的感兴趣区写出空文件</translation>
    </message>
    <message>
      <source>Index of the crops</source>
      <translation>裁剪索引</translation>
    </message>
    <message>
      <source>Open the crops in the map too</source>
      <translation>同时在地图中打开裁剪结果</translation>
    </message>
    <message>
      <source>Index of the point cloud crops</source>
      <translation>点云裁剪索引</translation>
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
      <translation>裁剪后的点云未加载到地图中：此 QGIS 没有点云数据提供程序（PDAL）。请从输出文件夹中打开它们（例如在 CloudCompare 中）。</translation>
    </message>
    <message>
      <source>PLY crops are not loaded into the map; open them from the output folder.</source>
      <translation>PLY 裁剪结果不会加载到地图中；请从输出文件夹中打开。</translation>
    </message>
    <message>
      <source>Cropping {n_rois} ROIs into {folder}</source>
      <translation>正在将 {n_rois} 个感兴趣区裁剪到 {folder}</translation>
    </message>
    <message>
      <source>Point cloud crops of {cloud} ({n})</source>
      <translation>{cloud} 的点云裁剪结果（{n}）</translation>
    </message>
    <message>
      <source>{cropped} ROIs cropped ({points:,} points), {n_empty} without points, {n_missed} outside the cloud.</source>
      <translation>已裁剪 {cropped} 个感兴趣区（{points:,} 个点），{n_empty} 个没有点，{n_missed} 个在点云范围外。</translation>
    </message>
    <message>
      <source>None of the {n_items} ROIs overlaps the point cloud: check that the ROIs and the cloud are in the right CRS (set 'Point cloud CRS' if the file has none or a wrong one).</source>
      <translation>{n_items} 个感兴趣区均未与点云重叠：请检查感兴趣区和点云的坐标系是否正确（如果文件没有坐标系或坐标系错误，请设置“点云坐标系”）。</translation>
    </message>
    <message>
      <source>Crop raster by ROIs</source>
      <translation>按感兴趣区裁剪栅格</translation>
    </message>
    <message>
      <source>Cuts every ROI (plot, tree, plant polygon) out of a GeoTIFF raster: an orthomosaic (DOM), a surface model (DSM) or a multispectral map, into one GeoTIFF per ROI in the output folder, named after the name field (made safe for file names and unique).

The raster is read in a single pass, each tile or strip once, so thousands of ROIs on rasters larger than memory are fast. Crops keep the raster's pixel grid, CRS and data type. Pixels outside the ROI are masked: RGB gets an alpha band, RGBA its alpha combined, DSM and multispectral get nodata (the raster's own, or -32767 for floating point and the type's extreme for integers when it has none). A pixel belongs to an ROI when its centre is inside (GDAL's rule); 'All touched' takes every pixel the ROI touches. Holes and multipart polygons are honoured. ROIs in another CRS are reprojected; ROIs outside the raster are reported and skipped.</source>
      <translation>将每个感兴趣区（小区、树木、植株多边形）从 GeoTIFF 栅格（正射影像（DOM）、数字表面模型（DSM）或多光谱图）中裁出，在输出文件夹中为每个感兴趣区生成一个 GeoTIFF，以名称字段命名（转换为可用作文件名的唯一名称）。

栅格只需读取一遍，每个瓦片或条带只读一次，因此即使栅格大于内存，处理数千个感兴趣区也很快。裁剪结果保留栅格的像元格网、坐标系和数据类型。感兴趣区外的像元会被掩膜：RGB 添加 alpha 波段，RGBA 与其 alpha 合并，DSM 和多光谱设为无数据值（使用栅格自身的无数据值；若没有，浮点型用 -32767，整型用该类型的极值）。像元中心位于感兴趣区内时，该像元属于此感兴趣区（GDAL 的规则）；“全部接触”则包含感兴趣区接触到的所有像元。考虑孔洞和多部件多边形。其他坐标系中的感兴趣区会被重投影；栅格范围外的感兴趣区会被报告并跳过。</translation>
    </message>
    <message>
      <source>Index of the crops (optional): the ROIs with the file of each ('crop_file', empty for a skipped ROI) and 'crop_status'. 'Open the crops in the map too' (off by default) opens up to 100 crops in one collapsed group below the ROI layer; a larger run opens the index only.</source>
      <translation>裁剪索引（可选）：各感兴趣区及其文件（'crop_file'，跳过的感兴趣区为空）和 'crop_status'。勾选“同时在地图中打开裁剪结果”（默认关闭）时，最多 100 个裁剪结果会在感兴趣区图层下方的一个折叠组中打开；更大的运行只打开索引。</translation>
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
      <source>Cropping {n_rois} ROIs out of {raster} into {folder}</source>
      <translation>正在从 {raster} 中裁剪 {n_rois} 个感兴趣区到 {folder}</translation>
    </message>
    <message>
      <source>Crops of {raster} ({n})</source>
      <translation>{raster} 的裁剪结果（{n}）</translation>
    </message>
    <message>
      <source>{n_files} GeoTIFFs written, {n_skipped} ROIs skipped.</source>
      <translation>已写出 {n_files} 个 GeoTIFF，跳过 {n_skipped} 个感兴趣区。</translation>
    </message>
    <message>
      <source>ROI '{name}' skipped: {reason}</source>
      <translation>已跳过感兴趣区“{name}”：{reason}</translation>
    </message>
    <message>
      <source>Export a training set</source>
      <translation>在原始照片上导出训练集</translation>
    </message>
    <message>
      <source>Turns objects labelled once on the map (polygons, or points with a radius) into a deep-learning training set on the raw photos: COCO instances (polygons and boxes), YOLO segment and detect labels with their data.yaml, and LabelMe files.

Each object is back-projected into every photo that sees it (heights from the DSM, lens distortion, occlusion tested on the DSM, photos ranked as Back-project ROIs does). An object is labelled in a photo when at least the minimum visible share of it is in the frame and not hidden by anything outside it (what its own canopy hides of it, such as the soil between its rows, does not count); its outline is clipped to the frame (hidden parts are not cut out). Best photos per object: keep only the k best-ranked (0 = all).

Tiles: with a tile size, photos are cut into tiles of that size (pixels) overlapping by the overlap; outlines are clipped to each tile and a part smaller than the minimum visible share of the object is dropped. Without, whole photos are copied.

Photos that do not decode (truncated, or not images) are named in the log and left out with their labels.

Values of the images: as stored (the default: the photos copied, tiles as PNG), temperature in °C or reflectance, as in Plot statistics from photos. PNG and JPEG cannot hold these values, so every image, whole photo or tile, is then a float32 TIFF (NAME.tif; the labels name it) with the unit in its GDAL metadata and NaN where a pixel is saturated or unreadable; a photo that holds no such values is left out with its labels. Networks train on either.

Split: whole images go to train or validation, none is left out: by field region (square cells of the region size, in the DSM's map units; an image goes with the region of most of its objects) or by photo. The log gives the images and labels of each set and warns when validation is empty or under half the fraction asked. An object seen in images of both sets is counted.

Tiles: a tile size that cuts a photo into more than 4096 tiles is refused.

Output folder: images/{train,val}, labels/{train,val} and data.yaml (YOLO segment), yolo_detect/ (YOLO detect), coco/instances_{train,val}.json, labelme/{train,val} and training_set.json (counts, rules and the list of files written). The folder holds only the set: other files in it are refused, with a list of them; an older set is replaced only with 'Overwrite existing files', which removes exactly the files its training_set.json lists.</source>
      <translation>将在地图上只标注一次的对象（多边形，或带半径的点）转换为原始照片上的深度学习训练集：COCO 实例（多边形和边界框）、YOLO 分割与检测标签及其 data.yaml，以及 LabelMe 文件。

每个对象被反投影到所有能看到它的照片中（高度取自 DSM，包含镜头畸变，在 DSM 上检验遮挡，并像“反投影 ROI”一样对照片排序）。当对象至少有最小可见比例位于画幅内且未被其自身以外的任何东西遮挡时（其自身冠层遮住的部分，例如行间的土壤，不计入），才在该照片中标注；其轮廓裁剪到画幅（被遮挡部分不切除）。每个对象的最佳照片：只保留排名前 k 张（0 = 全部）。

瓦片：给出瓦片大小时，照片被切成该大小（像素）、按重叠量相互重叠的瓦片；轮廓被精确裁剪到每个瓦片，小于对象最小可见比例的部分被舍弃。不给出时复制整张照片。

无法解码的照片（被截断，或不是图像）会在日志中列出，并连同其标签一起排除。

影像的数值：按存储的值（默认：复制照片，瓦片为 PNG）、以 °C 表示的温度或反射率，与“原始照片的小区统计”相同。PNG 和 JPEG 无法保存这些数值，因此此时每幅影像（整张照片或瓦片）都是 float32 TIFF（NAME.tif，标注指向它），其 GDAL 元数据中注明单位，饱和或无法读取的像素为 NaN；不含此类数值的照片连同其标注一起被排除。网络可以在任一种影像上训练。

划分：整张图像分到训练集或验证集，不排除任何图像：按田间区域（区域大小的正方形格网，DSM 的地图单位；图像归入其多数对象所在的区域）或按照片。日志给出每个集合的图像数和标签数，当验证集为空或少于所要求比例的一半时发出警告。出现在两个集合图像中的对象会被计数。

瓦片：若瓦片大小使一张照片被切成超过 4096 个瓦片，则拒绝执行。

输出文件夹：images/{train,val}、labels/{train,val} 和 data.yaml（YOLO 分割）、yolo_detect/（YOLO 检测）、coco/instances_{train,val}.json、labelme/{train,val} 以及 training_set.json（数量、规则和已写入文件的列表）。该文件夹只包含训练集：其中的其他文件会被拒绝并列出；只有在打开“覆盖已有文件”时才会替换旧的训练集，并且只删除其 training_set.json 所列出的文件。</translation>
    </message>
    <message>
      <source>Random seed of the split</source>
      <translation>划分的随机种子</translation>
    </message>
    <message>
      <source>Values of the images</source>
      <translation>影像的数值</translation>
    </message>
    <message>
      <source>Labelled objects (polygons or points)</source>
      <translation>已标注对象（多边形或点）</translation>
    </message>
    <message>
      <source>Class field</source>
      <translation>类别字段</translation>
    </message>
    <message>
      <source>Instance id field (default: feature id)</source>
      <translation>实例 ID 字段（默认：要素 ID）</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF)</source>
      <translation>数字表面模型 DSM（GeoTIFF）</translation>
    </message>
    <message>
      <source>Best photos per object (0 = all)</source>
      <translation>每个对象保留的最佳照片数（0 = 全部）</translation>
    </message>
    <message>
      <source>Tile size (pixels; 0 = whole photos)</source>
      <translation>瓦片大小（像素；0 = 整张照片）</translation>
    </message>
    <message>
      <source>Tile overlap (pixels)</source>
      <translation>瓦片重叠（像素）</translation>
    </message>
    <message>
      <source>Train/validation split</source>
      <translation>训练/验证划分</translation>
    </message>
    <message>
      <source>Training set folder</source>
      <translation>训练集文件夹</translation>
    </message>
    <message>
      <source>Labelled objects: no layer given, or it could not be loaded.</source>
      <translation>已标注对象：未给出图层，或无法加载。</translation>
    </message>
    <message>
      <source>EasyIDP</source>
      <translation>EasyIDP</translation>
    </message>
    <message>
      <source>Labelled objects</source>
      <translation>已标注对象</translation>
    </message>
    <message>
      <source>Radius of the disc around labelled points (map units)</source>
      <translation>标注点周围圆盘的半径（地图单位）</translation>
    </message>
    <message>
      <source>Minimum visible, unoccluded share of an object</source>
      <translation>对象可见且未被遮挡的最小比例</translation>
    </message>
    <message>
      <source>Validation fraction</source>
      <translation>验证集比例</translation>
    </message>
    <message>
      <source>Region size for the split (map units of the DSM)</source>
      <translation>划分用区域大小（DSM 的地图单位）</translation>
    </message>
    <message>
      <source>Training set: {warning}</source>
      <translation>训练集：{warning}</translation>
    </message>
    <message>
      <source>Labelled objects: polygons or points are needed, not lines.</source>
      <translation>已标注对象：需要多边形或点，而不是线。</translation>
    </message>
    <message>
      <source>By field region</source>
      <translation>按田间区域</translation>
    </message>
    <message>
      <source>By photo</source>
      <translation>按照片</translation>
    </message>
    <message>
      <source>Object '{name}': {why}</source>
      <translation>对象 '{name}'：{why}</translation>
    </message>
    <message>
      <source>Removed {n} file(s) of the older training set in the folder.</source>
      <translation>已删除文件夹中旧训练集的 {n} 个文件。</translation>
    </message>
    <message>
      <source>{split}: {images} images, {labels} labels of {objects} objects</source>
      <translation>{split}：{images} 张图像，{objects} 个对象的 {labels} 个标签</translation>
    </message>
    <message>
      <source>Labelled points need a positive disc radius (map units).</source>
      <translation>标注点需要正的圆盘半径（地图单位）。</translation>
    </message>
    <message>
      <source>Labelled objects: the layer has no field '{f}'.</source>
      <translation>已标注对象：图层没有字段 '{f}'。</translation>
    </message>
    <message>
      <source>Labelled objects: object '{name}' has no class in the field '{f}'. Fill it or filter the layer.</source>
      <translation>已标注对象：对象 '{name}' 在字段 '{f}' 中没有类别。请填写或筛选图层。</translation>
    </message>
    <message>
      <source>Fit plot grid to crop rows</source>
      <translation>将地块网格拟合到作物行</translation>
    </message>
    <message>
      <source>Moves a plot grid onto the crop that was really planted, as the orthomosaic shows it.

It tells the crop from weeds, margin grass and soil by its rows, not by greenness alone. From a vegetation index (ExG of an RGB orthomosaic, or NDVI of a multispectral one with its red and NIR bands) it finds the direction and spacing of the crop rows (the image's spectrum), then the grid's global rotation, spacing scale and shift from the plot block (all plots vote at once, so the field margins cannot pull it), then a per-plot shift, at most the bound, that centres each plot on its own rows: across them on the rows' positions (the median along each row, so that weeds and gaps do not pull it), along them on the row ends most of its rows agree on. Plots keep their size and shape. On the hard demo trial (margin grass, weeds, gaps, lodging; 3 seeds, 9 start grids up to 3°, 0.5 m and 3 % off) the fitted corners lie a median of 0.15–0.23 cm and at most 2.4 cm from the planted plots, and a correct grid moves by at most 0.93 cm.

Plots without rows (empty, bare soil), whose rows go on beyond their ends, or whose shift would exceed the bound are left in place: they keep the global correction only, with moved = 0 and the reason in fit_flag. Every plot gets shift_x, shift_y and shift_m (its own shift, m), fit_score (0–1: 1 when the plot's rows stop at its ends, 0 when they go on beyond them) and cover (its rows' strength over the median plot's). Features without a polygon are named in the log and written out unchanged.

The log gives the global correction and how many plots moved by more than the threshold. The orthomosaic is read in one pass by windows (any size; it is averaged to at most 16 million pixels), and the run can be cancelled. An orthomosaic with no vegetation under the plots is refused, and nothing is written. The output is in the orthomosaic's CRS, which must be projected in metres.</source>
      <translation>将小区网格移动到正射影像所示的实际播种作物上。

它依据作物的行来区分作物与杂草、田边草地和土壤，而不仅仅依据绿度。根据植被指数（RGB 正射影像的 ExG，或多光谱影像红光与近红外波段的 NDVI），先求出作物行的方向和行距（影像的频谱），再从小区块求出网格的全局旋转、间距缩放和平移（所有小区同时投票，田边无法将其拉偏），最后求出每个小区不超过上限的平移，使其以自身的行为中心：垂直于行按行的位置（沿每行取中位数，杂草和缺苗不会将其拉偏），沿行按多数行一致的行端。小区的大小和形状保持不变。在困难的演示试验田上（田边草地、杂草、缺苗、倒伏；3 个随机种子，9 个偏差达 3°、0.5 m 和 3 % 的初始网格），拟合后的角点与实际播种小区的距离中位数为 0.15–0.23 cm，最大 2.4 cm；正确的网格最多移动 0.93 cm。

没有行的小区（空小区、裸地）、行延伸到两端之外的小区，或平移将超过上限的小区保持原位：只接受全局校正，moved = 0，原因写入 fit_flag。每个小区都有 shift_x、shift_y 和 shift_m（自身的平移，m）、fit_score（0–1：小区的行在其两端终止时为 1，延伸到两端之外时为 0）以及 cover（其行强度相对于小区中位数的比值）。没有多边形的要素会在日志中列出，并按原样写出。

日志给出全局校正以及移动超过阈值的小区数。正射影像按窗口一次读取（任意大小；平均到最多 1600 万像素），运行可以取消。小区下方没有植被的正射影像会被拒绝，不写出任何内容。输出采用正射影像的坐标参考系，必须是以米为单位的投影坐标系。</translation>
    </message>
    <message>
      <source>Automatic (ExG for an RGB orthomosaic)</source>
      <translation>自动（RGB 正射影像用 ExG）</translation>
    </message>
    <message>
      <source>ExG (2G − R − B)/(R + G + B), RGB</source>
      <translation>ExG (2G − R − B)/(R + G + B)，RGB</translation>
    </message>
    <message>
      <source>NDVI (NIR − R)/(NIR + R), multispectral</source>
      <translation>NDVI (NIR − R)/(NIR + R)，多光谱</translation>
    </message>
    <message>
      <source>Name field</source>
      <translation>名称字段</translation>
    </message>
    <message>
      <source>The plots' names in labels and the log; default: plot_id, else the feature id</source>
      <translation>标注和日志中的小区名称；默认：plot_id，否则为要素 ID</translation>
    </message>
    <message>
      <source>Empty: 0.6 m + 9 % of the grid's half extent</source>
      <translation>留空：0.6 米 + 网格半幅宽的 9 %</translation>
    </message>
    <message>
      <source>Plot grid (polygons)</source>
      <translation>地块网格（多边形）</translation>
    </message>
    <message>
      <source>Orthomosaic (GeoTIFF)</source>
      <translation>正射影像（GeoTIFF）</translation>
    </message>
    <message>
      <source>Vegetation index</source>
      <translation>植被指数</translation>
    </message>
    <message>
      <source>Red band (ExG, NDVI)</source>
      <translation>红光波段（ExG、NDVI）</translation>
    </message>
    <message>
      <source>Green band (ExG)</source>
      <translation>绿光波段（ExG）</translation>
    </message>
    <message>
      <source>Blue band (ExG)</source>
      <translation>蓝光波段（ExG）</translation>
    </message>
    <message>
      <source>Near-infrared band (NDVI)</source>
      <translation>近红外波段（NDVI）</translation>
    </message>
    <message>
      <source>Search radius of the global correction (m)</source>
      <translation>整体校正的搜索半径（米）</translation>
    </message>
    <message>
      <source>Fitted plot grid</source>
      <translation>拟合后的地块网格</translation>
    </message>
    <message>
      <source>Plot grid: the layer has no plots.</source>
      <translation>地块网格：图层中没有地块。</translation>
    </message>
    <message>
      <source>Left in place (see fit_flag)</source>
      <translation>保留原位（见 fit_flag）</translation>
    </message>
    <message>
      <source>Fitted to the rows</source>
      <translation>已拟合到作物行</translation>
    </message>
    <message>
      <source>Largest per-plot shift (m)</source>
      <translation>每个地块的最大平移（米）</translation>
    </message>
    <message>
      <source>Report plots moved by more than (m)</source>
      <translation>报告平移超过此值的地块（米）</translation>
    </message>
    <message>
      <source>Bare below this share of the median plot's row strength</source>
      <translation>行强度低于小区中位数的此比例即视为裸地</translation>
    </message>
    <message>
      <source>Weak fit below this score</source>
      <translation>得分低于此值视为拟合较弱</translation>
    </message>
    <message>
      <source>{grid}: fitted to {ortho}</source>
      <translation>{grid}：已拟合到 {ortho}</translation>
    </message>
    <message>
      <source>Plot grid: {n} features have no polygon (NULL or empty geometry) and are skipped (written out unchanged, fit_flag '{flag}'): {names}.</source>
      <translation>小区网格：{n} 个要素没有多边形（NULL 或空几何），已跳过（按原样写出，fit_flag 为 '{flag}'）：{names}。</translation>
    </message>
    <message>
      <source>Plot grid: none of the {n} features has a polygon (all NULL or empty geometries).</source>
      <translation>小区网格：{n} 个要素都没有多边形（全部为 NULL 或空几何）。</translation>
    </message>
    <message>
      <source>Plot '{name}' left in place: {reason}.</source>
      <translation>地块“{name}”保持原位：{reason}。</translation>
    </message>
    <message>
      <source>… and {n} more plots left in place.</source>
      <translation>… 另有 {n} 个地块保持原位。</translation>
    </message>
    <message>
      <source>Forward-project polygons</source>
      <translation>将照片多边形正向投影到地图</translation>
    </message>
    <message>
      <source>Brings polygons drawn or detected on the raw photos (LabelMe, COCO, YOLO, or the photo-pixel layer written by Back-project ROIs) to the map, with their true position, area and perimeter: every vertex's pixel becomes a ray through the solved camera (lens distortion included) and its first hit on the DSM is the vertex on the map. Exact on any terrain and canopy (not a flat-ground homography).

Input, one of: a file (LabelMe .json, COCO .json, YOLO .txt); a folder (LabelMe .json files or YOLO .txt files, with classes.txt or data.yaml for class names); or a photo-pixel layer (x = column, y = −row, field 'photo'). Each image is matched to a photo of the project by file name; an image that is not in the project, or whose size differs from the camera's, is refused with its name. Detections on the tiles of a tiled training set (YOLO or LabelMe files named after the tiles) need its tile index (tiles.json): they are shifted back into their photo's pixels; COCO files of the set carry their tile windows themselves.

Edges are densified in the photo (a vertex every few pixels) so that long edges follow the surface. A vertex whose ray misses the DSM, leaves it or enters nodata is dropped and its polygon marked complete = false (and reported), never silently reshaped.

Merge: 'none' keeps one polygon per photo; 'union' merges the overlapping polygons of one label from several photos into one; 'best' keeps the best view (complete, highest score, most nadir); 'fuse' is for detections with scores (COCO results with the COCO images file, YOLO with confidence, LabelMe): duplicates in a photo are suppressed, the views of one object grouped by overlap and distance, and each object gets the outline most of its views agree on, its number of views, the photos that could have seen it (expected_views), mean and max score, its position and DSM height, and a confidence (mean score × views / expected views). Fields: photo, label, score, area_m2 and perimeter_m (planimetric, metres), views, complete, missing (vertices without a hit), and for 'fuse' expected_views, max_score and confidence. Output in the DSM's CRS, heights from the DSM.</source>
      <translation>将在原始照片上绘制或检测到的多边形（LabelMe、COCO、YOLO，或“将感兴趣区反投影到原始照片”写出的照片像素图层）投影到地图上，得到其真实位置、面积和周长：每个顶点的像素成为穿过解算相机（含镜头畸变）的一条射线，射线与 DSM 的第一个交点即为该顶点在地图上的位置。在任何地形和冠层上都精确（并非平地单应变换）。

输入，以下之一：一个文件（LabelMe .json、COCO .json、YOLO .txt）；一个文件夹（LabelMe .json 文件或 YOLO .txt 文件，类别名称来自 classes.txt 或 data.yaml）；或一个照片像素图层（x = 列，y = −行，字段 photo）。每幅图像按文件名与工程中的照片匹配；不在工程中或尺寸与相机不符的图像会被拒绝，并给出其名称。在分块训练集的分块上的检测结果（以分块命名的 YOLO 或 LabelMe 文件）需要其分块索引（tiles.json）：它们会被移回所在照片的像素坐标；该训练集的 COCO 文件自身带有分块窗口。

边在照片中加密（每隔几个像素一个顶点），使长边贴合地表。射线未击中 DSM、离开 DSM 或进入无数据值区域的顶点会被删除，其多边形标记为 complete = false（并报告），绝不会悄然改变形状。

合并：“无”为每张照片保留一个多边形；“多视图合并”将多张照片中同一标签的重叠多边形合并为一个；“最佳视图”保留最佳视图（完整、评分最高、最接近天底）。字段：photo、label、score、area_m2 和 perimeter_m（平面，米）、views、complete、missing（未击中的顶点）。输出采用 DSM 的坐标系，高度取自 DSM。

“融合”（fuse）用于带分数的检测（COCO 结果加 COCO 图像文件、带置信度的 YOLO、LabelMe）：抑制同一照片中的重复检测，按重叠和距离将同一对象的多个视图分组，每个对象得到多数视图一致的轮廓、视图数、本可看到它的照片数（expected_views）、平均和最大分数、位置及 DSM 高度，以及置信度（平均分数 × 视图数 / 期望视图数）；字段 expected_views、max_score、confidence。</translation>
    </message>
    <message>
      <source>Give exactly one of the three annotation inputs: a file, a folder or a photo-pixel layer.</source>
      <translation>请在三种标注输入中恰好提供一种：文件、文件夹或照片像素图层。</translation>
    </message>
    <message>
      <source>Merge the same object seen in several photos</source>
      <translation>合并在多张照片中看到的同一对象</translation>
    </message>
    <message>
      <source>COCO images file that a COCO results list refers to</source>
      <translation>COCO 结果列表所引用的 COCO 图像文件</translation>
    </message>
    <message>
      <source>Tile index (tiles.json), for annotations on tiles</source>
      <translation>切片索引（tiles.json），用于切片上的标注</translation>
    </message>
    <message>
      <source>Densify edges: a vertex every … photo pixels (0: off)</source>
      <translation>边加密：每隔 … 个照片像素一个顶点（0：关闭）</translation>
    </message>
    <message>
      <source>Polygons on the map</source>
      <translation>地图上的多边形</translation>
    </message>
    <message>
      <source>Give exactly one input: an annotation file, a folder of annotation files, or a photo-pixel layer.</source>
      <translation>请只给出一个输入：标注文件、标注文件所在的文件夹，或照片像素图层。</translation>
    </message>
    <message>
      <source>Incomplete: a vertex found no DSM</source>
      <translation>不完整：有顶点未命中 DSM</translation>
    </message>
    <message>
      <source>Complete</source>
      <translation>完整</translation>
    </message>
    <message>
      <source>Annotations, 1 of 3: a LabelMe, COCO or YOLO file</source>
      <translation>标注（三选一）：LabelMe、COCO 或 YOLO 文件</translation>
    </message>
    <message>
      <source>Annotations, 2 of 3: a LabelMe or YOLO folder</source>
      <translation>标注（三选一）：LabelMe 或 YOLO 文件夹</translation>
    </message>
    <message>
      <source>Annotations, 3 of 3: a photo-pixel polygon layer</source>
      <translation>标注（三选一）：照片像素多边形图层</translation>
    </message>
    <message>
      <source>Layer coordinates: x = column, y = −row.</source>
      <translation>图层坐标：x = 列，y = −行。</translation>
    </message>
    <message>
      <source>{what} on the map (through {project} onto {dsm})</source>
      <translation>地图上的 {what}（经 {project} 投影到 {dsm}）</translation>
    </message>
    <message>
      <source>{n} polygons from {p} photos written to the map ({i} incomplete).</source>
      <translation>已将来自 {p} 张照片的 {n} 个多边形写入地图（{i} 个不完整）。</translation>
    </message>
    <message>
      <source>None (one polygon per photo)</source>
      <translation>无（每张照片一个多边形）</translation>
    </message>
    <message>
      <source>Union of the views</source>
      <translation>多视图合并</translation>
    </message>
    <message>
      <source>Best view</source>
      <translation>最佳视图</translation>
    </message>
    <message>
      <source>Fuse detections (NMS, consensus outline, confidence)</source>
      <translation>融合检测（NMS、共识轮廓、置信度）</translation>
    </message>
    <message>
      <source>{n} lines or points skipped: only polygons are forward-projected by this tool.</source>
      <translation>已跳过 {n} 个线或点：此工具只正向投影多边形。</translation>
    </message>
    <message>
      <source>'{label}' is incomplete ({why}).</source>
      <translation>“{label}”不完整（{why}）。</translation>
    </message>
    <message>
      <source>Orthorectify ROIs</source>
      <translation>基于原始照片正射校正感兴趣区</translation>
    </message>
    <message>
      <source>Makes, for every ROI, a georeferenced image from a raw photo instead of the orthomosaic: sharper (no blending, ghosting or seamlines) and with true geometry. Each output pixel's ground point (its height from the DSM) is projected into the photo with the solved camera (lens distortion included) and the photo is sampled there (bilinear).

Photos: 'best' takes the best-scored photo of each ROI (the backward projection's score: visible share, view angle, resolution, distance from the centre); 'all' writes one image per photo that sees the ROI; 'named photo' uses the photo given. Pixel size: the GSD given (DSM CRS units), or 0 for the photo's native resolution at the ROI.

Output pixels outside the ROI, on DSM nodata, outside the photo, or hidden from the camera by the DSM (occlusion) are transparent (alpha 0).

Mask: 'occlusion mask' (the default) casts a ray from every output pixel's ground point to the camera and makes the pixel transparent where the DSM blocks it (a tree or a wall between them), so no pixel shows what stands in front of it; 'none' skips the rays and keeps every pixel the photo frames, as Orthority does (faster; hidden ground then shows the object that hides it).

One GeoTIFF per ROI (and photo, for 'all') in the output folder, in the DSM's CRS, with the photo's bands plus alpha. The photos are read from the paths stored in the project, or from the photos folder when given (matched by file name).

Values: as stored (the photo's bands and data type, the default), temperature in °C (FLIR radiometric JPEGs by the Planck curve, with the photo's object parameters unless given; temperature TIFFs by their preset or scale and offset) or reflectance (MicaSense and DJI multispectral band files), as in Plot statistics from photos. Temperature and reflectance images are float32 GeoTIFFs with the unit and what was applied in their GDAL metadata; pixels without a value, and those whose bilinear sample touches a saturated or unreadable photo pixel, are NaN (nodata, alpha 0).</source>
      <translation>为每个感兴趣区基于原始照片（而非正射影像）生成一幅地理配准图像：更清晰（无融合、重影或拼接线），且几何真实。每个输出像元的地面点（高度取自 DSM）通过解算相机（含镜头畸变）投影到照片中，并在该处对照片采样（双线性）。

照片：“每个感兴趣区的最佳照片”取各感兴趣区评分最高的照片（反投影的评分：可见比例、视角、分辨率、到中心的距离）；“能看到该感兴趣区的所有照片”为每张能看到该感兴趣区的照片各写出一幅图像；“指定的照片”使用给定的照片。像元大小：给定的 GSD（DSM 坐标系单位），或 0 表示照片在该感兴趣区处的原始分辨率。

位于感兴趣区外、DSM 无数据值处、照片外，或被 DSM 遮挡而相机看不到（遮挡）的输出像元为透明（alpha 0）。

掩膜：“遮挡掩膜”（默认）从每个输出像元的地面点向相机投射一条射线，在 DSM 挡住射线的地方（两者之间有树或墙）将该像元设为透明，因此不会有像元显示挡在它前面的物体；“无”不投射射线，保留照片拍到的每个像元，与 Orthority 的行为相同（更快；被遮挡的地面会显示遮挡它的物体）。

在输出文件夹中为每个感兴趣区（选择“所有照片”时为每个感兴趣区和照片）生成一个 GeoTIFF，采用 DSM 的坐标系，包含照片的波段及 alpha 波段。照片从工程中存储的路径读取；若给出了照片文件夹，则从该文件夹读取（按文件名匹配）。

数值：按存储的值（照片的波段和数据类型，默认）、以 °C 表示的温度（FLIR 辐射测量 JPEG 按普朗克曲线换算，未给出时使用照片自带的目标参数；温度 TIFF 按其预设或比例与偏移换算）或反射率（MicaSense 与大疆多光谱波段文件），与“原始照片的小区统计”相同。温度和反射率影像为 float32 GeoTIFF，其 GDAL 元数据中注明单位及所做的换算；没有数值的像素，以及双线性采样触及饱和或无法读取的照片像素的像素，为 NaN（无数据，alpha 为 0）。</translation>
    </message>
    <message>
      <source>Index of the images (optional): one feature per image, the ROI with its file ('image_file'), photo, visible share and pixel size. 'Open the images in the map too' (off by default) opens up to 100 images in one collapsed group below the ROI layer; a larger run opens the index only.</source>
      <translation>影像索引（可选）：每幅影像一个要素，含感兴趣区及其文件（'image_file'）、照片、可见比例和像元大小。勾选“同时在地图中打开影像”（默认关闭）时，最多 100 幅影像会在感兴趣区图层下方的一个折叠组中打开；更大的运行只打开索引。</translation>
    </message>
    <message>
      <source>Pixel size (DSM CRS units; 0: the photo's native resolution)</source>
      <translation>像元大小（DSM 坐标系单位；0：照片的原始分辨率）</translation>
    </message>
    <message>
      <source>Index of the images</source>
      <translation>图像索引</translation>
    </message>
    <message>
      <source>Open the images in the map too</source>
      <translation>同时在地图中打开影像</translation>
    </message>
    <message>
      <source>Values</source>
      <translation>数值</translation>
    </message>
    <message>
      <source>Folder of the raw photos (default: the paths in the project)</source>
      <translation>原始照片文件夹（默认：工程中的路径）</translation>
    </message>
    <message>
      <source>Photos</source>
      <translation>照片</translation>
    </message>
    <message>
      <source>Photo label (for 'A named photo')</source>
      <translation>照片标签（用于“指定的照片”）</translation>
    </message>
    <message>
      <source>Mask</source>
      <translation>掩膜</translation>
    </message>
    <message>
      <source>Orthorectified ROI images</source>
      <translation>正射校正的感兴趣区图像</translation>
    </message>
    <message>
      <source>Number of images written</source>
      <translation>写出的图像数量</translation>
    </message>
    <message>
      <source>{rois} from raw photos ({n})</source>
      <translation>基于原始照片的 {rois}（{n}）</translation>
    </message>
    <message>
      <source>{n} orthorectified ROI images written to {folder}; {s} skipped.</source>
      <translation>已将 {n} 幅正射校正的感兴趣区图像写入 {folder}；跳过 {s} 幅。</translation>
    </message>
    <message>
      <source>Best photo of each ROI</source>
      <translation>每个感兴趣区的最佳照片</translation>
    </message>
    <message>
      <source>Every photo that sees the ROI</source>
      <translation>能看到该感兴趣区的所有照片</translation>
    </message>
    <message>
      <source>A named photo</source>
      <translation>指定的照片</translation>
    </message>
    <message>
      <source>Occlusion mask (hide the ground the DSM hides from the camera)</source>
      <translation>遮挡掩膜（隐藏 DSM 使相机看不到的地面）</translation>
    </message>
    <message>
      <source>None (every pixel the photo frames, as Orthority)</source>
      <translation>无（照片拍到的每个像元，与 Orthority 相同）</translation>
    </message>
    <message>
      <source>{what}: no image ({why}).</source>
      <translation>{what}：无图像（{why}）。</translation>
    </message>
    <message>
      <source>Plot statistics from photos</source>
      <translation>原始照片的小区统计</translation>
    </message>
    <message>
      <source>Measures every ROI (plot) in every raw photo that sees it, and gives each ROI one robust value across its views. Raw photos have no ghosting or seamlines and true colour from near-nadir views.

Inputs as Back-project ROIs: the ROI polygons, the photogrammetry project, the heights of the ROI vertices and a DSM; the backward projection runs here, unless its photo-pixel layer (the OUTPUT of Back-project ROIs) is given, which is then used as it is.

Per ROI and photo, the pixels whose centre is inside the ROI's polygon (clipped to the frame) give: per band the mean, median, standard deviation and chosen percentiles, in the photo's own values (8-bit, 16-bit or float; never converted to 8-bit); the vegetation indices ExG, ExGR, VARI, GLI (red, green, blue) and NDVI, NDRE (for multispectral photos, name the bands, e.g. 'blue,green,red,rededge,nir'); the canopy cover (share of pixels whose NDVI, else ExG, is at or above the threshold: the one given, or Otsu's over all views); the pixel count and the GSD. With a DSM, pixels whose line of sight meets the surface outside the ROI (hidden by a tree, a neighbour, a wall) are left out and their share is reported.

Across views, per ROI: the median of each statistic (score-weighted if asked), its MAD, minimum and maximum over the views used (visible share at least the minimum; the best ones by score when a maximum is set), their number, each view's deviation from its ROI's value and each ROI's largest (the disagreement; about 1 is typical for the field, several times more flags a shadow, wind, a bad pose). Oblique views see the sides of tall canopy, so cover and indices grow with the view angle: the default keeps the 3 best views.

Values: as stored (the photos' own numbers), temperature in °C (FLIR radiometric JPEGs of the Zenmuse XT/XT2, Vue Pro R, Duo Pro R and FLIR handhelds, converted by the Planck curve with the photo's constants and object parameters, each of which can be overridden; or temperature TIFFs with a stated scale and offset; DJI R-JPEGs must be converted with DJI's tool first) or reflectance (MicaSense and DJI multispectral band files, from their irradiance sensor). The band files of one capture are one view: each band is measured through its own camera, one row per ROI × capture with a column per band, and indices come from the band means and medians of the same ROI. Temperature and reflectance put the unit in the column names (temp_c_mean, nir_refl_median); saturated pixels are left out. Each view also gets its photo's acquisition time and the sun's zenith, azimuth and phase angle (sun–plot–camera).

Outputs: a table of every ROI × photo with its statistics; the ROIs with the across-view values; optionally one PNG per ROI with the views used side by side and their values.</source>
      <translation>在每张看到它的原始照片中测量每个 ROI（小区），并为每个 ROI 给出跨视图的一个稳健值。原始照片没有重影或拼接线，近天底视图的颜色真实。

输入与“将感兴趣区反投影到原始照片”相同：ROI 多边形、摄影测量工程、ROI 顶点高度和 DSM；反投影在此运行，除非给出其照片像素图层（“将感兴趣区反投影到原始照片”的 OUTPUT），此时按原样使用。

对每个 ROI 和照片，像素中心位于 ROI 多边形内（裁剪到画幅）的像素给出：每个波段的均值、中位数、标准差和所选百分位数，采用照片自身的数值（8 位、16 位或浮点；从不转换为 8 位）；植被指数 ExG、ExGR、VARI、GLI（红、绿、蓝）以及 NDVI、NDRE（多光谱照片请命名波段，例如 'blue,green,red,rededge,nir'）；冠层覆盖度（NDVI，否则 ExG，大于或等于阈值的像素比例：给定的阈值，或所有视图上的 Otsu 阈值）；像素数和 GSD。给出 DSM 时，视线在 ROI 之外碰到地表的像素（被树木、相邻植株、墙遮挡）会被排除，并报告其比例。

跨视图，对每个 ROI：各统计量的中位数（如要求则按得分加权）、其 MAD、所用视图上的最小值和最大值（可见比例不低于最小值；设置最大数量时取得分最高者）、视图数、每个视图相对其 ROI 值的偏差以及每个 ROI 的最大偏差（不一致度；约 1 对该田块是典型的，数倍以上则提示阴影、风或错误的位姿）。倾斜视图会看到高冠层的侧面，因此覆盖度和指数随视角增大：默认保留最好的 3 个视图。

值：按存储的值（照片自身的数值）、°C 温度（Zenmuse XT/XT2、Vue Pro R、Duo Pro R 及 FLIR 手持机的 FLIR 辐射测量 JPEG，用照片的常数和目标参数（均可覆盖）按普朗克曲线换算；或给定比例和偏移的温度 TIFF；DJI R-JPEG 须先用 DJI 的工具转换）或反射率（MicaSense 和 DJI 多光谱波段文件，依据其辐照度传感器）。一次拍摄的各波段文件是一个视图：每个波段通过其自身的相机测量，每个 ROI × 拍摄一行、每个波段一列，指数由同一 ROI 的波段均值和中位数计算。温度和反射率会在列名中加入单位（temp_c_mean、nir_refl_median）；饱和像素被排除。每个视图还给出照片的拍摄时间以及太阳天顶角、方位角和相位角（太阳–小区–相机）。

输出：每个 ROI × 照片及其统计量的表；带跨视图值的 ROI；可选地，每个 ROI 一张 PNG，并排显示所用视图及其数值。</translation>
    </message>
    <message>
      <source>Band names of the photos (comma-separated)</source>
      <translation>照片的波段名称（逗号分隔）</translation>
    </message>
    <message>
      <source>Default: red,green,blue for 3 bands; e.g. blue,green,red,rededge,nir</source>
      <translation>默认：3 个波段时为 red,green,blue；例如 blue,green,red,rededge,nir</translation>
    </message>
    <message>
      <source>Values measured</source>
      <translation>测量的值</translation>
    </message>
    <message>
      <source>UTC offset of the photos' clock (hours)</source>
      <translation>照片时钟的 UTC 偏移（小时）</translation>
    </message>
    <message>
      <source>For photos that do not state it (the sun's angles need UTC); empty: none</source>
      <translation>用于未记录偏移的照片（太阳角度需要 UTC 时间）；留空：无</translation>
    </message>
    <message>
      <source>Back-projection (photo-pixel layer; empty: run it here)</source>
      <translation>反投影结果（照片像素图层；留空：在此运行）</translation>
    </message>
    <message>
      <source>Leave out pixels hidden by the DSM (when a DSM is given)</source>
      <translation>排除被 DSM 遮挡的像素（给出 DSM 时）</translation>
    </message>
    <message>
      <source>Statistics of every band and index</source>
      <translation>每个波段和指数的统计量</translation>
    </message>
    <message>
      <source>Percentiles (comma-separated, 0–100; empty: none)</source>
      <translation>百分位数（逗号分隔，0–100；留空：无）</translation>
    </message>
    <message>
      <source>Vegetation indices (those the bands allow)</source>
      <translation>植被指数（波段允许的）</translation>
    </message>
    <message>
      <source>Cover threshold on NDVI or ExG (empty: Otsu's)</source>
      <translation>NDVI 或 ExG 的覆盖度阈值（留空：Otsu 阈值）</translation>
    </message>
    <message>
      <source>Minimum visible share of a ROI in a view used</source>
      <translation>所用视图中 ROI 的最小可见比例</translation>
    </message>
    <message>
      <source>Best views used per ROI (0 = all)</source>
      <translation>每个 ROI 使用的最佳视图数（0 = 全部）</translation>
    </message>
    <message>
      <source>Weight the views by their score (weighted median)</source>
      <translation>按得分对视图加权（加权中位数）</translation>
    </message>
    <message>
      <source>Statistics of every ROI × photo</source>
      <translation>每个 ROI × 照片的统计量</translation>
    </message>
    <message>
      <source>ROIs with their across-view statistics</source>
      <translation>带跨视图统计量的 ROI</translation>
    </message>
    <message>
      <source>Preview per ROI (the views used, with their values)</source>
      <translation>每个 ROI 的预览（所用视图及其数值）</translation>
    </message>
    <message>
      <source>No DSM given: hidden pixels are not left out.</source>
      <translation>未给出 DSM：不排除被遮挡的像素。</translation>
    </message>
    <message>
      <source>Back-projection</source>
      <translation>反投影</translation>
    </message>
    <message>
      <source>Mean</source>
      <translation>均值</translation>
    </message>
    <message>
      <source>Median</source>
      <translation>中位数</translation>
    </message>
    <message>
      <source>Standard deviation</source>
      <translation>标准差</translation>
    </message>
    <message>
      <source>{rois}: plot statistics from the photos of {project}</source>
      <translation>{rois}：来自 {project} 照片的小区统计</translation>
    </message>
    <message>
      <source>{rois}: statistics per photo</source>
      <translation>{rois}：每张照片的统计量</translation>
    </message>
    <message>
      <source>Back-projection from the layer '{name}': {k} ROI × photo pairs.</source>
      <translation>来自图层“{name}”的反投影：{k} 个 ROI × 照片对。</translation>
    </message>
    <message>
      <source>{n} ROI(s) without a view used: {names}</source>
      <translation>{n} 个 ROI 没有可用的视图：{names}</translation>
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
      <translation>对每个感兴趣区（小区、树木、植株多边形），统计点云（.las、.laz 或 .ply）中位于其内的点及其离地高度：冠层高度、其百分位数和点密度，可用于株高或生物量模型等。

结果为带原有属性的感兴趣区图层，并新增：count（内部点数）、density（点云坐标系中每平方单位的点数：对以米为单位的点云即每 m²）、z_min、z_mean、z_max（点的 Z）、ground（点下方地面 Z 的平均值）、h_mean、h_max，以及所需每个高度百分位数的 h_pNN（离地高度：Z 减去地面）（默认 5、50、95、99；p99 可稳健地代表冠层顶部）。

地面：在每个点下方采样的 DSM/DTM 栅格（出苗前飞行得到的裸土 DSM，或 DTM）；或单一地面高度；若两者都没有，则使用每个感兴趣区自身的最低点：其 Z 的给定百分位数（高级，默认 1）。栅格和高度必须与点云采用相同的 Z 单位和高程基准。

LAS/LAZ 文件自带坐标系；PLY 文件没有，因此需要为其设置“点云坐标系”（没有坐标系的 LAS 文件也一样）。其他坐标系中的感兴趣区会被重投影。没有任何点的感兴趣区会在日志中列出；其 count 和 density 为 0，Z 和高度为空（NULL），绝不为 0。</translation>
    </message>
    <message>
      <source>ROIs (polygons)</source>
      <translation>感兴趣区（多边形）</translation>
    </message>
    <message>
      <source>Ground: DSM or DTM raster (GeoTIFF)</source>
      <translation>地面：DSM 或 DTM 栅格（GeoTIFF）</translation>
    </message>
    <message>
      <source>Ground otherwise: percentile of each ROI's Z</source>
      <translation>其他情况下的地面：每个感兴趣区 Z 值的百分位数</translation>
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
      <translation>地面：请给出 DSM/DTM 栅格或单一地面高度，不能同时给出。</translation>
    </message>
    <message>
      <source>Ground DSM/DTM</source>
      <translation>地面 DSM/DTM</translation>
    </message>
    <message>
      <source>The ROI layer's own fields with the names of the statistics are replaced by the new values.</source>
      <translation>感兴趣区图层中与统计量同名的原有字段将被新值替换。</translation>
    </message>
    <message>
      <source>Ground: one height for all ROIs (cloud Z units)</source>
      <translation>地面：所有感兴趣区使用同一高度（点云 Z 单位）</translation>
    </message>
    <message>
      <source>{rois}: point cloud heights of {cloud}</source>
      <translation>{rois}：{cloud} 的点云高度</translation>
    </message>
    <message>
      <source>Statistics of {n_rois} ROIs written, {n} with points{shown}.</source>
      <translation>已写出 {n_rois} 个感兴趣区的统计，其中 {n} 个含点{shown}。</translation>
    </message>
    <message>
      <source>Ground: the raster {name} under every point.</source>
      <translation>地面：每个点下方的栅格 {name}。</translation>
    </message>
    <message>
      <source>Ground: percentile {ground_pct:g} of each ROI's Z.</source>
      <translation>地面：每个感兴趣区 Z 的第 {ground_pct:g} 百分位数。</translation>
    </message>
    <message>
      <source>None of the {n_rois} ROIs contains a point of the cloud: check that the ROIs and the cloud are in the right CRS (set 'Point cloud CRS' if the file has none or a wrong one) and the Z range.</source>
      <translation>{n_rois} 个感兴趣区均不包含点云中的点：请检查感兴趣区和点云的坐标系是否正确（如果文件没有坐标系或坐标系错误，请设置“点云坐标系”），以及 Z 范围。</translation>
    </message>
    <message>
      <source>The ground raster {name} has no data under the points of {n} of the {total} ROIs (outside it or nodata): their heights above ground are empty. Check that it covers the ROIs.</source>
      <translation>地面栅格 {name} 在 {total} 个感兴趣区中 {n} 个的点下方没有数据（位于其范围外或为无数据值）：这些感兴趣区的离地高度为空。请检查它是否覆盖了感兴趣区。</translation>
    </message>
    <message>
      <source>{n} ROI(s) contain no point (outside the cloud, in a gap, or outside the Z range); their statistics are empty: feature id {ids}.</source>
      <translation>{n} 个感兴趣区不含任何点（位于点云外、空洞中或 Z 范围外）；其统计为空：要素 ID {ids}。</translation>
    </message>
    <message>
      <source>Ground: {height:g} for every ROI.</source>
      <translation>地面：所有感兴趣区均为 {height:g}。</translation>
    </message>
    <message>
      <source> (map colours: {field})</source>
      <translation>（地图着色：{field}）</translation>
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
      <translation>从数字表面模型（DSM）为每个感兴趣区赋予高度，作为其顶点的 Z 值以及属性 height（采用 DSM 的单位和高程基准）。结果为 PolygonZ 类型的感兴趣区图层，可直接用于反投影到原始照片。

按多边形：对中心位于感兴趣区内的 DSM 像元计算统计量（平均值、中位数、最小值、最大值、某一百分位数（如冠层顶部用 90，地面用 5）、标准差，或 EasyIDP 的 pmin/pmax：低于该百分位数 / 高于 100 减该百分位数的值的平均值），感兴趣区可用正缓冲距离扩大或用负缓冲距离收缩（DSM 的地图单位）。每个顶点都取该高度。
按顶点：每个顶点处的 DSM 高度（双线性或最近像元），或在设置缓冲距离时，取该顶点缓冲距离内像元的统计量；此时 height 为各顶点高度的平均值。

忽略无数据值像元。没有任何有效像元的感兴趣区，其高度保留为空（NULL），Z 为 NaN，并在日志中列出；绝不会赋为 0。</translation>
    </message>
    <message>
      <source>Per polygon: one statistic of the DSM pixels inside</source>
      <translation>按多边形：内部 DSM 像元的一个统计量</translation>
    </message>
    <message>
      <source>Per vertex: the DSM height at each vertex</source>
      <translation>按顶点：每个顶点处的 DSM 高度</translation>
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
      <source>Percentile (0–100; for percentile, pmin and pmax)</source>
      <translation>百分位数（0–100；用于 percentile、pmin 和 pmax）</translation>
    </message>
    <message>
      <source>{rois}: height {what} from {dsm}</source>
      <translation>{rois}：来自 {dsm} 的高度 {what}</translation>
    </message>
    <message>
      <source>ROI '{name}': {reason}; its height is left empty.</source>
      <translation>感兴趣区“{name}”：{reason}；其高度留空。</translation>
    </message>
    <message>
      <source>Heights ({what}) of {n} ROIs: {lo:.3f} to {hi:.3f} (DSM units), {null} empty (NULL).</source>
      <translation>{n} 个感兴趣区的高度（{what}）：{lo:.3f} 至 {hi:.3f}（DSM 单位），{null} 个为空（NULL）。</translation>
    </message>
    <message>
      <source>Heights of {n} ROIs: all empty (NULL): {reason}.</source>
      <translation>{n} 个 ROI 的高度全部为空（NULL）：{reason}。</translation>
    </message>
    <message>
      <source>Heights of {n} ROIs: all empty (NULL): the DSM has no valid pixel under any of them.</source>
      <translation>{n} 个感兴趣区的高度：全部为空（NULL）：DSM 在它们下方都没有有效像元。</translation>
    </message>
    <message>
      <source>see the warnings above for each ROI</source>
      <translation>各 ROI 的原因见上方警告</translation>
    </message>
    <message>
      <source>Plot traits over a season</source>
      <translation>生长季小区性状</translation>
    </message>
    <message>
      <source>Time series</source>
      <translation>时间序列</translation>
    </message>
    <message>
      <source>Traits of every ROI (plot, tree) on every date of a season of surveys: plant height from the DSMs, canopy cover, band means and a vegetation index from the orthomosaics, heights from the point clouds. Each file is read once for all ROIs; the files are shared out to worker processes on this computer, or to a Dask cluster.

Survey table: a CSV file or a table layer with the columns date (YYYY-MM-DD), orthomosaic, dsm, point_cloud and project (file paths, absolute or relative to the table's folder; empty cells allowed); optional: bands (the orthomosaic's band names in order, e.g. blue,green,red,rededge,nir: NDVI needs red and nir) and crs (for files without one, e.g. PLY). Rows with a missing file, an unreadable raster or a CRS that cannot be related to the ROIs are reported by row and left out; the rest completes. The project column is read but not used by the traits yet.

Traits: height_pNN (percentiles of the DSM above the ground, metres); cover (share of the ROI whose vegetation index is above the threshold, 0-1; Otsu's automatic threshold per orthomosaic, or a given one); exg (excess green, RGB) or ndvi (named bands); mean_&lt;band&gt; (band means); cloud_points and cloud_height_pNN (point clouds).

Ground: a bare-soil DSM or DTM of the season (a flight before emergence): a plane is fitted to it under each ROI. Without one, each ROI's ground is the plane through the lowest heights (the given percentile) in a 3 × 3 grid over it, which needs bare soil between the plants.

Workers: processes on this computer. Dask scheduler (advanced): tcp://host:8786 to run on a Dask cluster (the files must be at the same paths on every worker), or 'local' for a Dask cluster of 'Workers' processes on this computer.

Outputs: the long table (roi, date, trait, value); the ROIs with the traits of their latest date (styled by height); growth curves as a PNG (a panel per ROI, or per group when there are many ROIs and a group field); optionally the crops, in &lt;date&gt;/&lt;orthomosaic|dsm|point_cloud&gt;/ folders.</source>
      <translation>计算一个生长季中每个感兴趣区（小区、树木）在每次航测日期的性状：来自 DSM 的株高，来自正射影像的冠层覆盖度、波段均值和植被指数，以及来自点云的高度。每个文件只读取一次即可处理所有感兴趣区；文件会分配给本机上的工作进程，或分配给 Dask 集群。

航测表：CSV 文件或表格图层，包含 date（YYYY-MM-DD）、orthomosaic、dsm、point_cloud 和 project 列（文件路径，可为绝对路径或相对于表所在文件夹的路径；允许空单元格）；可选列：bands（正射影像按顺序排列的波段名称，如 blue,green,red,rededge,nir：NDVI 需要 red 和 nir）和 crs（用于没有坐标系的文件，如 PLY）。文件缺失、栅格无法读取或坐标系无法与感兴趣区关联的行会按行报告并排除；其余部分照常完成。project 列会被读取，但目前尚未用于性状计算。

性状：height_pNN（DSM 高出地面部分的百分位数，米）；cover（植被指数高于阈值的感兴趣区面积比例，0-1；每幅正射影像使用 Otsu 自动阈值，或使用给定阈值）；exg（超绿指数，RGB）或 ndvi（需命名波段）；mean_&lt;band&gt;（波段均值）；cloud_points 和 cloud_height_pNN（点云）。

地面：该生长季的裸土 DSM 或 DTM（出苗前的一次飞行）：在每个感兴趣区下方对其拟合一个平面。若没有，则每个感兴趣区的地面为通过其上 3 × 3 格网中最低高度（给定百分位数）的平面，这要求植株之间有裸土。

工作进程数：本机上的进程。Dask 调度器（高级）：tcp://host:8786 表示在 Dask 集群上运行（文件在每个 worker 上的路径必须相同），'local' 表示在本机上使用由“工作进程数”个进程组成的 Dask 集群。

输出：长表（roi、date、trait、value）；带最新日期性状的感兴趣区（按高度设置样式）；PNG 格式的生长曲线（每个感兴趣区一个面板，若感兴趣区很多且设置了分组字段，则每组一个面板）；可选的裁剪结果，位于 &lt;date&gt;/&lt;orthomosaic|dsm|point_cloud&gt;/ 文件夹中。</translation>
    </message>
    <message>
      <source>Dask scheduler (tcp://host:port or 'local')</source>
      <translation>Dask 调度器（tcp://host:port 或 'local'）</translation>
    </message>
    <message>
      <source>Empty: processes on this computer</source>
      <translation>留空：使用本机上的进程</translation>
    </message>
    <message>
      <source>Survey table (CSV file or table layer)</source>
      <translation>航测表（CSV 文件或表格图层）</translation>
    </message>
    <message>
      <source>Name field (unique; default: feature id)</source>
      <translation>名称字段（唯一；默认：要素 ID）</translation>
    </message>
    <message>
      <source>Group field (treatment, variety: colours the curves)</source>
      <translation>分组字段（处理、品种：用于曲线着色）</translation>
    </message>
    <message>
      <source>Traits</source>
      <translation>性状</translation>
    </message>
    <message>
      <source>Ground: bare-soil DSM or DTM of the season</source>
      <translation>地面：本季的裸土 DSM 或 DTM</translation>
    </message>
    <message>
      <source>Ground without a DTM: percentile of the lowest heights</source>
      <translation>无 DTM 时的地面：最低高度的百分位数</translation>
    </message>
    <message>
      <source>Cover threshold on the vegetation index (empty: Otsu)</source>
      <translation>植被指数的覆盖度阈值（留空：Otsu）</translation>
    </message>
    <message>
      <source>Worker processes</source>
      <translation>工作进程数</translation>
    </message>
    <message>
      <source>Crops per date (folder)</source>
      <translation>各日期的裁剪结果（文件夹）</translation>
    </message>
    <message>
      <source>Traits per ROI and date (long table)</source>
      <translation>按感兴趣区和日期的性状（长表）</translation>
    </message>
    <message>
      <source>ROIs with their latest traits</source>
      <translation>带最新性状的感兴趣区</translation>
    </message>
    <message>
      <source>Growth curves (PNG)</source>
      <translation>生长曲线（PNG）</translation>
    </message>
    <message>
      <source>PNG files (*.png)</source>
      <translation>PNG 文件 (*.png)</translation>
    </message>
    <message>
      <source>Survey table: no table given, or it could not be loaded.</source>
      <translation>航测表：未给出表，或无法加载该表。</translation>
    </message>
    <message>
      <source>Traits: choose at least one.</source>
      <translation>性状：请至少选择一项。</translation>
    </message>
    <message>
      <source>Ground</source>
      <translation>地面</translation>
    </message>
    <message>
      <source>No trait could be computed: every survey row was left out (see the messages above).</source>
      <translation>无法计算任何性状：所有航测行均被排除（见上方消息）。</translation>
    </message>
    <message>
      <source>{n} surveys, {r} ROIs, traits: {t}</source>
      <translation>{n} 次航测，{r} 个感兴趣区，性状：{t}</translation>
    </message>
    <message>
      <source>{v} values of {k} traits for {r} ROIs on {d} dates in {s:.0f} s ({e}); {p} rows or files left out.</source>
      <translation>在 {s:.0f} s 内为 {r} 个感兴趣区在 {d} 个日期计算了 {k} 种性状，共 {v} 个值（{e}）；排除了 {p} 行或文件。</translation>
    </message>
    <message>
      <source>{rois}: latest traits</source>
      <translation>{rois}：最新性状</translation>
    </message>
    <message>
      <source>{rois}: traits per date</source>
      <translation>{rois}：各日期性状</translation>
    </message>
    <message>
      <source>Height from the DSM</source>
      <translation>来自 DSM 的高度</translation>
    </message>
    <message>
      <source>Canopy cover</source>
      <translation>冠层覆盖度</translation>
    </message>
    <message>
      <source>Band means</source>
      <translation>波段均值</translation>
    </message>
    <message>
      <source>Vegetation index (ExG or NDVI)</source>
      <translation>植被指数（ExG 或 NDVI）</translation>
    </message>
    <message>
      <source>Heights from the point cloud</source>
      <translation>来自点云的高度</translation>
    </message>
    <message>
      <source>Survey {p}</source>
      <translation>航测表：{p}</translation>
    </message>
    <message>
      <source>Left out: {p}</source>
      <translation>已排除：{p}</translation>
    </message>
    <message>
      <source>QGIS's own {packages}: the plugin does not replace QGIS's packages; use a newer QGIS.</source>
      <translation>QGIS 自带的 {packages}：插件不会替换 QGIS 自带的包；请使用更新版本的 QGIS。</translation>
    </message>
    <message>
      <source>{tool} needs Python packages that QGIS's Python does not have: {packages}.</source>
      <translation>{tool} 需要 QGIS 的 Python 中没有的 Python 包：{packages}。</translation>
    </message>
    <message>
      <source>Nothing was installed.</source>
      <translation>未安装任何内容。</translation>
    </message>
    <message>
      <source>The plugin's Python packages are installed with the Install button the QGIS desktop shows when one is missing, or by running:
{command}</source>
      <translation>缺少插件所需的 Python 包时，可通过 QGIS 桌面端显示的“安装”按钮安装，或运行：
{command}</translation>
    </message>
    <message>
      <source>{name} {version} (needs {spec})</source>
      <translation>{name} {version}（需要 {spec}）</translation>
    </message>
    <message>
      <source>{python} is Python {got}, but QGIS runs Python {want}; QGIS's own interpreter was not found</source>
      <translation>{python} 是 Python {got}，但 QGIS 运行的是 Python {want}；未找到 QGIS 自带的解释器</translation>
    </message>
    <message>
      <source>{error}. Install the missing Python package for QGIS's Python ({python}).</source>
      <translation>{error}。请为 QGIS 的 Python（{python}）安装缺少的 Python 包。</translation>
    </message>
    <message>
      <source>QGIS's Python interpreter {python} cannot run: {error}</source>
      <translation>QGIS 的 Python 解释器 {python} 无法运行：{error}</translation>
    </message>
    <message>
      <source>To install them, click Install in the EasyIDP message bar of the QGIS desktop, or run:
{command}</source>
      <translation>要安装它们，请在 QGIS 桌面端的 EasyIDP 消息栏中点击“安装”，或运行：
{command}</translation>
    </message>
    <message>
      <source>Installing Python packages for EasyIDP</source>
      <translation>正在为 EasyIDP 安装 Python 包</translation>
    </message>
    <message>
      <source>Cancel</source>
      <translation>取消</translation>
    </message>
    <message>
      <source>Some tools need Python packages that QGIS's Python lacks: {packages}.</source>
      <translation>部分工具需要 QGIS 的 Python 中缺少的 Python 包：{packages}。</translation>
    </message>
    <message>
      <source>Install</source>
      <translation>安装</translation>
    </message>
    <message>
      <source>Download them with pip into your QGIS profile; QGIS's own packages are not changed.</source>
      <translation>使用 pip 将它们下载到您的 QGIS 用户配置文件中；不会改动 QGIS 自带的包。</translation>
    </message>
    <message>
      <source>Every Python package EasyIDP needs is installed.</source>
      <translation>EasyIDP 所需的 Python 包均已安装。</translation>
    </message>
    <message>
      <source>Installing {packages} …</source>
      <translation>正在安装 {packages} …</translation>
    </message>
    <message>
      <source>Python packages installed: {packages}.</source>
      <translation>已安装 Python 包：{packages}。</translation>
    </message>
    <message>
      <source>Restart QGIS to use them: an older copy is already loaded.</source>
      <translation>请重启 QGIS 以使用它们：已加载了旧版本。</translation>
    </message>
    <message>
      <source>nothing was missing</source>
      <translation>没有缺少的包</translation>
    </message>
    <message>
      <source>Installation cancelled; nothing was changed. To install later, run:
{command}</source>
      <translation>安装已取消，未做任何更改。如需稍后安装，请运行：
{command}</translation>
    </message>
    <message>
      <source>Installing the Python packages failed: {reason}. Run this command in a terminal to see why:
{command}</source>
      <translation>安装 Python 包失败：{reason}。请在终端中运行以下命令查看原因：
{command}</translation>
    </message>
    <message>
      <source>still missing after pip: {packages}</source>
      <translation>pip 运行后仍缺少：{packages}</translation>
    </message>
    <message>
      <source>exit status {code}</source>
      <translation>退出状态 {code}</translation>
    </message>
    <message>
      <source>you may not read it (permissions)</source>
      <translation>没有读取权限</translation>
    </message>
    <message>
      <source>it is empty (0 bytes)</source>
      <translation>文件为空（0 字节）</translation>
    </message>
    <message>
      <source>it is JSON but not GeoJSON (no FeatureCollection)</source>
      <translation>它是 JSON，但不是 GeoJSON（没有 FeatureCollection）</translation>
    </message>
    <message>
      <source>it is not UTF-8 text, so not GeoJSON</source>
      <translation>它不是 UTF-8 文本，因此不是 GeoJSON</translation>
    </message>
    <message>
      <source>it is not a TIFF file (it starts with {head!r})</source>
      <translation>它不是 TIFF 文件（开头为 {head!r}）</translation>
    </message>
    <message>
      <source>GDAL cannot open it ({error})</source>
      <translation>GDAL 无法打开它（{error}）</translation>
    </message>
    <message>
      <source>not a format it knows</source>
      <translation>不是它认识的格式</translation>
    </message>
    <message>
      <source>{name}: {path} exists but cannot be read as a layer: {why}. Check the file, or save it again from the program that made it.</source>
      <translation>{name}：{path} 存在，但无法作为图层读取：{why}。请检查该文件，或用生成它的程序重新保存。</translation>
    </message>
    <message>
      <source>it is not valid JSON ({error}); it may be cut short</source>
      <translation>它不是有效的 JSON（{error}）；文件可能被截断</translation>
    </message>
    <message>
      <source>ROI file not found: {path}</source>
      <translation>找不到 ROI 文件：{path}</translation>
    </message>
    <message>
      <source>{path}: file not found.</source>
      <translation>{path}：找不到文件。</translation>
    </message>
    <message>
      <source>The ROIs have no CRS: set one on the layer before using it.</source>
      <translation>ROI 没有坐标参考系：请先为图层设置坐标参考系再使用。</translation>
    </message>
    <message>
      <source>The ROI layer has no features.</source>
      <translation>ROI 图层没有要素。</translation>
    </message>
    <message>
      <source>None of the {count} ROIs overlaps the raster {raster}. Raster extent {raster_extent}, ROI extent {roi_extent} (both in {crs}). Check that the ROI layer and the raster cover the same area and that the ROI layer's CRS is set correctly.</source>
      <translation>{count} 个 ROI 都不与栅格 {raster} 重叠。栅格范围 {raster_extent}，ROI 范围 {roi_extent}（均为 {crs}）。请检查 ROI 图层与栅格是否覆盖同一区域，以及 ROI 图层的坐标参考系是否设置正确。</translation>
    </message>
    <message>
      <source>No ROI is seen by any photo: check that the ROIs lie in the surveyed area and in the right CRS.</source>
      <translation>没有任何照片拍到 ROI：请检查 ROI 是否位于测区内、坐标参考系是否正确。</translation>
    </message>
    <message>
      <source>Nothing to write: give a crops folder, a previews folder or both.</source>
      <translation>没有可写出的内容：请指定裁剪文件夹、预览文件夹或两者。</translation>
    </message>
    <message>
      <source>GDAL cannot open it as a GeoPackage; {size:.0f} KiB</source>
      <translation>GDAL 无法将其作为 GeoPackage 打开；{size:.0f} KiB</translation>
    </message>
    <message>
      <source>it is on a read-only file system</source>
      <translation>它位于只读文件系统上</translation>
    </message>
    <message>
      <source>{output}: {folder} is a file, not a folder. Choose another file.</source>
      <translation>{output}：{folder} 是文件而不是文件夹。请选择其他文件。</translation>
    </message>
    <message>
      <source>{output}: the folder {folder} does not exist and cannot be created. Create it, or choose another file.</source>
      <translation>{output}：文件夹 {folder} 不存在且无法创建。请先创建它，或选择其他文件。</translation>
    </message>
    <message>
      <source>'{a}' and '{b}' are both {path}: one would replace the other. Choose two files.</source>
      <translation>“{a}”和“{b}”都是 {path}：其中一个会替换另一个。请选择两个不同的文件。</translation>
    </message>
    <message>
      <source>you may not write there ({reason})</source>
      <translation>没有写入权限（{reason}）</translation>
    </message>
    <message>
      <source>{output}: {path} cannot be written: {why}. Choose a folder you can write to.</source>
      <translation>{output}：无法写入 {path}：{why}。请选择可写入的文件夹。</translation>
    </message>
    <message>
      <source>{output}: {path} is also the input '{input}'. Inputs are never overwritten: choose another file.</source>
      <translation>{output}：{path} 同时也是输入“{input}”。输入绝不会被覆盖：请选择其他文件。</translation>
    </message>
    <message>
      <source>{name}: {value} is not a number; give a finite value.</source>
      <translation>{name}：{value} 不是数字；请给出一个有限值。</translation>
    </message>
    <message>
      <source>{name}: {value:g} is outside the range {lo}–{hi}.</source>
      <translation>{name}：{value:g} 超出范围 {lo}–{hi}。</translation>
    </message>
    <message>
      <source>{output}: another run ({holder}) is writing {path}; nothing was written. Wait for it to finish, or choose another file.</source>
      <translation>{output}：另一个运行（{holder}）正在写入 {path}；未写入任何内容。请等待其完成，或选择其他文件。</translation>
    </message>
    <message>
      <source>{output}: {path} was not a valid GeoPackage ({why}), the leftover of an interrupted run; it is replaced.</source>
      <translation>{output}：{path} 不是有效的 GeoPackage（{why}），是中断的运行留下的；将被替换。</translation>
    </message>
    <message>
      <source>{output}: {path} already exists and nothing was written. Choose another file, or tick 'Overwrite existing files' (advanced) to replace it.</source>
      <translation>{output}：{path} 已存在，未写出任何内容。请选择其他文件，或勾选“覆盖已有文件”（高级）以替换它。</translation>
    </message>
    <message>
      <source>{name}: {value} is not one of the choices ({opts}).</source>
      <translation>{name}：{value} 不是可选值之一（{opts}）。</translation>
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
      <source>Percentiles: '{token}' is not a number from 0 to 100. Give percentiles separated by commas, e.g. 5,50,95.</source>
      <translation>百分位数：“{token}”不是 0 到 100 之间的数。请给出以逗号分隔的百分位数，例如 5,50,95。</translation>
    </message>
    <message>
      <source>EasyIDP photo viewer</source>
      <translation>EasyIDP 照片查看器</translation>
    </message>
    <message>
      <source>Photogrammetry projects (*.psx *.psz *.xml *.p4d *.opf *.json);;All files (*)</source>
      <translation>摄影测量项目 (*.psx *.psz *.xml *.p4d *.opf *.json);;所有文件 (*)</translation>
    </message>
    <message>
      <source>Project</source>
      <translation>项目</translation>
    </message>
    <message>
      <source>Used when no DSM is chosen: one ground height, in the project's vertical reference</source>
      <translation>未选择 DSM 时使用：一个地面高度，采用项目的高程基准</translation>
    </message>
    <message>
      <source>Ground height without a DSM</source>
      <translation>无 DSM 时的地面高度</translation>
    </message>
    <message>
      <source>Layer in photo pixels</source>
      <translation>照片像素图层</translation>
    </message>
    <message>
      <source>Click a point</source>
      <translation>点击一个点</translation>
    </message>
    <message>
      <source>Selected plots</source>
      <translation>所选小区</translation>
    </message>
    <message>
      <source>Show layer</source>
      <translation>显示图层</translation>
    </message>
    <message>
      <source>EasyIDP viewer: decoding photos</source>
      <translation>EasyIDP 查看器：正在解码照片</translation>
    </message>
    <message>
      <source>Images (*.png *.jpg *.tif)</source>
      <translation>图像 (*.png *.jpg *.tif)</translation>
    </message>
    <message>
      <source>LabelMe (*.json)</source>
      <translation>LabelMe (*.json)</translation>
    </message>
    <message>
      <source>Save</source>
      <translation>保存</translation>
    </message>
    <message>
      <source>Photo</source>
      <translation>照片</translation>
    </message>
    <message>
      <source>ROI</source>
      <translation>ROI</translation>
    </message>
    <message>
      <source>Rank</source>
      <translation>排名</translation>
    </message>
    <message>
      <source>Score</source>
      <translation>得分</translation>
    </message>
    <message>
      <source>View angle (°)</source>
      <translation>视角 (°)</translation>
    </message>
    <message>
      <source>GSD</source>
      <translation>GSD</translation>
    </message>
    <message>
      <source>Visible</source>
      <translation>可见</translation>
    </message>
    <message>
      <source>Occluded</source>
      <translation>遮挡</translation>
    </message>
    <message>
      <source>Save the shown crop…</source>
      <translation>保存显示的裁剪…</translation>
    </message>
    <message>
      <source>Save the outline as LabelMe…</source>
      <translation>将轮廓保存为 LabelMe…</translation>
    </message>
    <message>
      <source>Choose the photogrammetry project first.</source>
      <translation>请先选择摄影测量项目。</translation>
    </message>
    <message>
      <source>No layer in photo pixels: run Back-project ROIs first.</source>
      <translation>没有照片像素图层：请先运行“将 ROI 反投影到原始照片”。</translation>
    </message>
    <message>
      <source>A clicked point has no outline: select plots.</source>
      <translation>点击的点没有轮廓：请选择小区。</translation>
    </message>
    <message>
      <source>Select plots in a polygon layer first.</source>
      <translation>请先在多边形图层中选择小区。</translation>
    </message>
    <message>
      <source>{n} ROI × photo pairs of {layer}.</source>
      <translation>{layer} 的 {n} 个 ROI × 照片对。</translation>
    </message>
    <message>
      <source>{photo}: {roi}, rank {rank}, score {score:.2f}</source>
      <translation>{photo}：{roi}，排名 {rank}，得分 {score:.2f}</translation>
    </message>
    <message>
      <source>{n} photos see it.</source>
      <translation>{n} 张照片能看到它。</translation>
    </message>
    <message>
      <source>No photo sees it: {why}</source>
      <translation>没有照片能看到它：{why}</translation>
    </message>
    <message>
      <source>Could not write {path}.</source>
      <translation>无法写入 {path}。</translation>
    </message>
    <message>
      <source>Written: {path}</source>
      <translation>已写入：{path}</translation>
    </message>
    <message>
      <source>Emissivity (empty: the photo's)</source>
      <translation>发射率（留空：照片的值）</translation>
    </message>
    <message>
      <source>Object distance, m (empty: the photo's)</source>
      <translation>目标距离，米（留空：照片的值）</translation>
    </message>
    <message>
      <source>Reflected apparent temperature, °C (empty: the photo's)</source>
      <translation>反射表观温度，°C（留空：照片的值）</translation>
    </message>
    <message>
      <source>Atmospheric temperature, °C (empty: the photo's)</source>
      <translation>大气温度，°C（留空：照片的值）</translation>
    </message>
    <message>
      <source>Relative humidity, % (empty: the photo's)</source>
      <translation>相对湿度，%（留空：照片的值）</translation>
    </message>
    <message>
      <source>IR window temperature, °C (empty: the photo's)</source>
      <translation>红外窗口温度，°C（留空：照片的值）</translation>
    </message>
    <message>
      <source>IR window transmission, 0–1 (empty: the photo's)</source>
      <translation>红外窗口透过率，0–1（留空：照片的值）</translation>
    </message>
    <message>
      <source>Temperature TIFFs store</source>
      <translation>温度 TIFF 的存储方式</translation>
    </message>
    <message>
      <source>°C</source>
      <translation>°C</translation>
    </message>
    <message>
      <source>Kelvin</source>
      <translation>开尔文</translation>
    </message>
    <message>
      <source>°C × 10</source>
      <translation>°C × 10</translation>
    </message>
    <message>
      <source>°C × 1000</source>
      <translation>°C × 1000</translation>
    </message>
    <message>
      <source>Centi-kelvin (K × 100)</source>
      <translation>厘开尔文（K × 100）</translation>
    </message>
    <message>
      <source>Temperature TIFF scale (°C = stored × scale + offset)</source>
      <translation>温度 TIFF 的比例（°C = 存储值 × 比例 + 偏移）</translation>
    </message>
    <message>
      <source>Empty: the preset's</source>
      <translation>留空：使用预设值</translation>
    </message>
    <message>
      <source>Temperature TIFF offset, °C (empty: the preset)</source>
      <translation>温度 TIFF 的偏移，°C（留空：预设）</translation>
    </message>
    <message>
      <source>As stored</source>
      <translation>按存储的值</translation>
    </message>
    <message>
      <source>Temperature (°C)</source>
      <translation>温度（°C）</translation>
    </message>
    <message>
      <source>Reflectance</source>
      <translation>反射率</translation>
    </message>
    <message>
      <source>Photo viewer: which photos see this?</source>
      <translation>照片查看器：哪些照片能看到这里？</translation>
    </message>
    <message>
      <source>Point cloud (.las, .laz or .ply)</source>
      <translation>点云（.las、.laz 或 .ply）</translation>
    </message>
    <message>
      <source>Needed for PLY, and for LAS/LAZ without a CRS; otherwise read from the file (a CRS given here replaces the file's)</source>
      <translation>PLY 以及没有坐标参考系的 LAS/LAZ 需要；否则从文件读取（此处给出的坐标参考系会替代文件中的）</translation>
    </message>
    <message>
      <source>Point cloud CRS</source>
      <translation>点云坐标参考系</translation>
    </message>
    <message>
      <source>Off: only the index opens (when it is set to open). On: the files too, in one collapsed group below the ROI layer; none when there are more than {n} (the log says where they are).</source>
      <translation>关闭：只打开索引（若设为打开）。开启：文件也在感兴趣区图层下方的一个折叠组中打开；超过 {n} 个时一个也不打开（日志会说明文件位置）。</translation>
    </message>
    <message>
      <source>Other photos of the ROI</source>
      <translation>该感兴趣区的其他照片</translation>
    </message>
    <message>
      <source>The ROI's best photo (rank 1)</source>
      <translation>该感兴趣区的最佳照片（排名 1）</translation>
    </message>
    <message>
      <source>No file (skipped: see its status)</source>
      <translation>无文件（已跳过：见其状态）</translation>
    </message>
    <message>
      <source>File written</source>
      <translation>已写入文件</translation>
    </message>
    <message>
      <source>{n} files are more than the {limit} loaded into the map: open them from the output folder.</source>
      <translation>{n} 个文件超过了加载到地图中的上限 {limit}：请从输出文件夹中打开它们。</translation>
    </message>
    <message>
      <source>In photo pixels, not loaded into the map: {path}</source>
      <translation>照片像素，未加载到地图：{path}</translation>
    </message>
    <message>
      <source>For Pix4D without a *_wkt.prj file, OpenSfM without OpenDroneMap, or a Metashape chunk CRS that PROJ cannot use; for a folder of photos, default: their UTM zone</source>
      <translation>用于没有 *_wkt.prj 文件的 Pix4D、没有 OpenDroneMap 的 OpenSfM，或 PROJ 无法使用其坐标参考系的 Metashape 块；照片文件夹默认使用照片所在的 UTM 带</translation>
    </message>
    <message>
      <source>Camera heights (a folder of photos)</source>
      <translation>相机高度（照片文件夹）</translation>
    </message>
    <message>
      <source>Take-off height (m; a folder of photos)</source>
      <translation>起飞点高度（米；照片文件夹）</translation>
    </message>
    <message>
      <source>In the DSM's vertical reference: added to the photos' relative altitude</source>
      <translation>以 DSM 的高程基准表示：加到照片的相对高度上</translation>
    </message>
    <message>
      <source>Metashape .psx/.psz/.xml; Pix4D .p4d, project or params folder; OpenDroneMap folder or reconstruction.json; OPF project.opf; or a folder of drone photos (cameras from their EXIF/XMP tags: rough, see the log's uncertainty)</source>
      <translation>Metashape .psx/.psz/.xml；Pix4D .p4d、项目文件夹或 params 文件夹；OpenDroneMap 文件夹或 reconstruction.json；OPF project.opf；或无人机照片文件夹（相机来自其 EXIF/XMP 标签：较粗略，见日志中的不确定度）</translation>
    </message>
    <message>
      <source>Metashape chunk (label or index) or OpenSfM reconstruction index: needed when the project has several</source>
      <translation>Metashape 块（名称或序号）或 OpenSfM 重建序号：项目中有多个时需要</translation>
    </message>
    <message>
      <source>Project CRS (override)</source>
      <translation>项目坐标参考系（覆盖）</translation>
    </message>
    <message>
      <source>Altitude in the tags (GNSS; RTK: ellipsoidal)</source>
      <translation>标签中的高度（GNSS；RTK：椭球高）</translation>
    </message>
    <message>
      <source>Relative altitude + the take-off height below</source>
      <translation>相对高度 + 下方的起飞点高度</translation>
    </message>
    <message>
      <source>Relative altitude + the DSM under the first photo</source>
      <translation>相对高度 + 第一张照片下方的 DSM</translation>
    </message>
    <message>
      <source>Camera heights from the DSM under the first photo need a DSM: set 'DSM', or give the take-off height.</source>
      <translation>由第一张照片下方的 DSM 求相机高度需要 DSM：请设置“DSM”，或给出起飞点高度。</translation>
    </message>
    <message>
      <source>Photogrammetry project or folder of photos</source>
      <translation>摄影测量项目或照片文件夹</translation>
    </message>
    <message>
      <source>Chunk or reconstruction</source>
      <translation>块或重建</translation>
    </message>
    <message>
      <source>Camera heights from the relative altitude need the take-off height: set 'Take-off height'.</source>
      <translation>由相对高度求相机高度需要起飞点高度：请设置“起飞点高度”。</translation>
    </message>
    <message>
      <source>Photogrammetry project: none given ({what}).</source>
      <translation>摄影测量工程：未给出（{what}）。</translation>
    </message>
    <message>
      <source>{path}: the project's CRS is unknown (a Pix4D project without *_wkt.prj, or an OpenSfM dataset without GPS): set 'Project CRS'.</source>
      <translation>{path}：工程的坐标系未知（没有 *_wkt.prj 的 Pix4D 工程，或没有 GPS 的 OpenSfM 数据集）：请设置“工程坐标系”。</translation>
    </message>
    <message>
      <source>{n} camera(s) are not aligned and have no pose: {names}</source>
      <translation>{n} 台相机未对齐，没有位姿：{names}</translation>
    </message>
    <message>
      <source>Name field (default: feature id)</source>
      <translation>名称字段（默认：要素 ID）</translation>
    </message>
    <message>
      <source>Heights of the ROI vertices</source>
      <translation>感兴趣区顶点的高度</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF): vertex heights and occlusion test</source>
      <translation>DSM（GeoTIFF）：顶点高度与遮挡检测</translation>
    </message>
    <message>
      <source>Height attribute</source>
      <translation>高度属性</translation>
    </message>
    <message>
      <source>Constant ground height: give the height, or choose another height source.</source>
      <translation>固定地面高度：请给出高度，或选择其他高度来源。</translation>
    </message>
    <message>
      <source>Geometry Z (3-D polygons)</source>
      <translation>几何 Z 值（三维多边形）</translation>
    </message>
    <message>
      <source>DSM, sampled at every vertex</source>
      <translation>DSM，在每个顶点采样</translation>
    </message>
    <message>
      <source>Attribute (one height per ROI)</source>
      <translation>属性（每个感兴趣区一个高度）</translation>
    </message>
    <message>
      <source>Constant ground height</source>
      <translation>固定地面高度</translation>
    </message>
    <message>
      <source>Constant ground height (project vertical reference)</source>
      <translation>固定地面高度（工程高程基准）</translation>
    </message>
    <message>
      <source>Heights from the DSM: choose the DSM raster, or another height source.</source>
      <translation>高度来自 DSM：请选择 DSM 栅格，或选择其他高度来源。</translation>
    </message>
    <message>
      <source>Heights from an attribute: choose the height attribute of the ROI layer.</source>
      <translation>高度来自属性：请选择感兴趣区图层的高度属性。</translation>
    </message>
  </context>
</TS>