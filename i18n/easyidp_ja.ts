<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="ja">
  <context>
    <name>EasyIDP</name>
    <message>
      <source>Back-project ROIs</source>
      <translation>ROI を元画像へ逆投影</translation>
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
      <translation>Metashape または Pix4D プロジェクトの元画像（撮影写真）のうち、各 ROI（区画、樹木、植物のポリゴン）が写っているものを、プロジェクトで解かれたカメラを使ってすべて見つけます（EasyIDP の back2raw）。元画像はオルソモザイクより鮮明で、シームラインもありません。

入力：ROI ポリゴン、プロジェクト（Metashape の .psx/.psz/カメラの .xml、Pix4D の .p4d またはその 1_initial/params フォルダ内の任意のファイル、またはドローン写真のフォルダ。写真の EXIF と XMP タグから概略のカメラを作り、各ピクセル地物はその予想誤差 uncertainty_px を持ちます）、ROI 頂点の高さ。高さは、ジオメトリの Z（例：「DSM から ROI の高さを取得」の出力）、各頂点でサンプリングした数値表層モデル（DSM）、数値属性、または一定の地面の高さから取得します（高さはプロジェクトの高さ基準で指定します。地理座標系の Metashape チャンクでは楕円体高）。写真フォルダ：写真を移動した場合の写真の場所（ファイル名で照合）。

各 ROI は頂点を高密度化してレンズ歪みを含めて投影し、写真の枠で切り取ります（「ROI 全体のみ」の場合は、ROI 全体が写真に収まるときのみ残します）。DSM がある場合は、ROI 内の地表上の点への視線について遮蔽を判定します。遮蔽されずに見える割合が最小値未満の写真は除外し、残りの写真はスコア（視線角、地上解像度、写真中心からの距離、見える割合）で順位付けします。

出力：写真ピクセル単位の ROI（x = 列、y = −行。QGIS でジオリファレンスなしに開いた元画像に重なります。'photo' で絞り込んでください）。ROI × 写真ごとに 1 地物で、スコア、順位、視線角、地上画素寸法（GSD）、各割合を持ちます。地図上の ROI の概要（写真の枚数と最良の写真）。オプションで、EasyIDP の JSON {roi: {photo: [[x, y], ...]}}、元画像の切り出し（ROI をアルファとした PNG、16 ビットまたはマルチバンドの写真では TIFF。それぞれ JSON のサイドカー付き）、ROI ごとに最良の写真を示すプレビュー PNG 1 枚。

切り出し画像の値：保存された値のまま（写真そのものの画素、既定）、°C の温度（FLIR ラジオメトリック JPEG はプランク曲線で換算し、指定がなければ写真の対象パラメータを使用。温度 TIFF はプリセットまたはスケールとオフセットで換算）、または反射率（MicaSense と DJI のマルチスペクトルバンドファイル）。「元画像からの区画統計」と同じです。温度と反射率の切り出し画像は float32 TIFF で、単位と適用した換算を GDAL メタデータに記録し、飽和または読み取れない画素は NaN（nodata）になります。そのような値を持たない写真は理由とともにスキップされます。</translation>
    </message>
    <message>
      <source>Only this photo</source>
      <translation>この写真のみ</translation>
    </message>
    <message>
      <source>Its file name or camera label; empty: every photo</source>
      <translation>ファイル名またはカメラのラベル。空欄：すべての写真</translation>
    </message>
    <message>
      <source>Apply the lens distortion (off for undistorted photos)</source>
      <translation>レンズ歪みを適用（歪み補正済みの写真ではオフ）</translation>
    </message>
    <message>
      <source>Margin around the crops (pixels)</source>
      <translation>切り出しの周囲の余白（ピクセル）</translation>
    </message>
    <message>
      <source>Values of the crops</source>
      <translation>切り出し画像の値</translation>
    </message>
    <message>
      <source>photos</source>
      <translation>枚の写真</translation>
    </message>
    <message>
      <source>Photos folder (when the photos moved; matched by file name)</source>
      <translation>写真フォルダ（写真を移動した場合。ファイル名で照合）</translation>
    </message>
    <message>
      <source>ROIs partly outside a photo</source>
      <translation>写真から一部はみ出す ROI</translation>
    </message>
    <message>
      <source>Test occlusion against the DSM (when a DSM is given)</source>
      <translation>DSM で遮蔽を判定（DSM を指定した場合）</translation>
    </message>
    <message>
      <source>Minimum visible, unoccluded share of a ROI in a photo</source>
      <translation>写真内で遮蔽されずに見える ROI の最小割合</translation>
    </message>
    <message>
      <source>Best photos to keep per ROI (0 = all)</source>
      <translation>ROI ごとに残す最良の写真の枚数（0 = すべて）</translation>
    </message>
    <message>
      <source>ROIs in photo pixels (x = column, y = −row)</source>
      <translation>写真ピクセル単位の ROI（x = 列、y = −行）</translation>
    </message>
    <message>
      <source>ROIs with their photo count and best photo</source>
      <translation>写真の枚数と最良の写真付き ROI</translation>
    </message>
    <message>
      <source>EasyIDP back2raw JSON</source>
      <translation>EasyIDP back2raw JSON</translation>
    </message>
    <message>
      <source>Crops of the raw photos</source>
      <translation>元画像の切り出し</translation>
    </message>
    <message>
      <source>Preview per ROI (its best photos)</source>
      <translation>ROI ごとのプレビュー（最良の写真）</translation>
    </message>
    <message>
      <source>No DSM given: occlusion is not tested.</source>
      <translation>DSM が指定されていないため、遮蔽は判定しません。</translation>
    </message>
    <message>
      <source>The values chosen apply to the crops and previews only, and neither folder was given.</source>
      <translation>選んだ値は切り出し画像とプレビューにだけ使われますが、どちらのフォルダも指定されていません。</translation>
    </message>
    <message>
      <source>Cutting the ROIs out of the photos…</source>
      <translation>写真から ROI を切り出しています…</translation>
    </message>
    <message>
      <source>The ROIs in photo pixels open in the EasyIDP photo viewer (toolbar), over their photos, not in the map.</source>
      <translation>写真ピクセルの ROI は地図ではなく、EasyIDP 写真ビューア（ツールバー）で写真の上に開きます。</translation>
    </message>
    <message>
      <source>Clip them to the photo frame</source>
      <translation>写真の枠で切り取る</translation>
    </message>
    <message>
      <source>Drop the photo (whole ROIs only)</source>
      <translation>写真を除外（ROI 全体のみ）</translation>
    </message>
    <message>
      <source>Projecting {n} ROIs into {m} photos ({h})</source>
      <translation>{n} 個の ROI を {m} 枚の写真に投影しています（{h}）</translation>
    </message>
    <message>
      <source>{rois} in the photos of {project} (photo pixels)</source>
      <translation>{project} の写真上の {rois}（写真ピクセル）</translation>
    </message>
    <message>
      <source>{rois}: photos of {project} that see them</source>
      <translation>{rois}：ROI が写る {project} の写真</translation>
    </message>
    <message>
      <source>{k} ROI × photo pairs for {seen} of {n} ROIs; {u} ROIs in no photo.</source>
      <translation>{n} 個中 {seen} 個の ROI について ROI × 写真の組が {k} 組あります。どの写真にも写らない ROI は {u} 個です。</translation>
    </message>
    <message>
      <source>ROI '{name}': {why}</source>
      <translation>ROI '{name}'：{why}</translation>
    </message>
    <message>
      <source>… and {n} more ROIs without a photo</source>
      <translation>… ほかに写真のない ROI が {n} 個</translation>
    </message>
    <message>
      <source>{n} crops and {p} previews written.</source>
      <translation>切り出し {n} 件とプレビュー {p} 件を書き出しました。</translation>
    </message>
    <message>
      <source>Photo {label} skipped: {why}</source>
      <translation>写真 {label} をスキップしました：{why}</translation>
    </message>
    <message>
      <source>Overwrite existing files</source>
      <translation>既存のファイルを上書き</translation>
    </message>
    <message>
      <source>Otherwise the tool stops before writing anything when an output already exists</source>
      <translation>オフの場合、出力が既に存在すると、何も書き込まずにツールを停止します</translation>
    </message>
    <message>
      <source>Cameras and footprints</source>
      <translation>カメラ位置と撮影範囲</translation>
    </message>
    <message>
      <source>Photogrammetry projects</source>
      <translation>写真測量プロジェクト</translation>
    </message>
    <message>
      <source>Reads the solved cameras of an Agisoft Metashape project (.psx with its .files folder, .psz, or an exported cameras .xml), a Pix4D project (.p4d, the project folder or its 1_initial/params folder: choose any file in it, e.g. *_pmatrix.txt) or an OpenDroneMap/OpenSfM project (choose opensfm/reconstruction.json in the ODM project folder; Python scripts may give the folder itself) and draws, for every aligned camera, its position and the part of the ground its photo sees. Run it first to check that a project was read right.

Chunk: the Metashape chunk (label or index), or the OpenSfM reconstruction (index of a partial model; by default the largest, as the log says).

The footprint is the photo border (densified, with the lens distortion) cast onto the DSM, or onto a constant ground height when no DSM is given. Attributes: label, photo path, enabled, height above ground (m), view angle from nadir (degrees), and for footprints the area (m²) and whether the whole border reached the ground's data (complete; where the DSM ends the footprint continues on a plane at the ground height under the camera). A camera at or below the ground gets no footprint and is named in the log.

Metashape projects with rolling-shutter compensation: each photo has one pose per image row (the motion Metashape estimated during the readout); the footprints, like every projection, use it, and the log says when it is applied.

Outputs are in the output CRS if one is chosen, else in the DSM's CRS, else in the map's CRS, else in the photogrammetry project's (the log says which). A Pix4D params folder without *_wkt.prj needs the project CRS. ODM projects bring ODM's CRS (that of its orthophoto and DSM); an OpenSfM dataset without ODM uses the WGS 84 / UTM zone of its reference point unless a project CRS is set. Heights of the DSM or the ground height must be in the project's vertical reference (for a Metashape chunk in a geographic CRS: ellipsoidal heights; for ODM: the heights of its DSM).</source>
      <translation>Agisoft Metashape プロジェクト（.files フォルダを伴う .psx、.psz、またはエクスポートしたカメラの .xml）、Pix4D プロジェクト（.p4d、プロジェクトフォルダ、またはその 1_initial/params フォルダ：その中の任意のファイル、例えば *_pmatrix.txt を選択します）、または OpenDroneMap/OpenSfM プロジェクト（ODM プロジェクトフォルダ内の opensfm/reconstruction.json を選択します。Python スクリプトではフォルダ自体を指定できます）の解かれたカメラを読み込み、位置合わせされた各カメラについて、その位置と写真に写る地面の範囲を描画します。プロジェクトが正しく読み込まれたかを確認するため、最初に実行してください。

チャンク：Metashape のチャンク（ラベルまたはインデックス）、または OpenSfM の再構成（部分モデルのインデックス。既定ではログに示される最大のもの）。

撮影範囲（フットプリント）は、写真の縁（高密度化し、レンズ歪みを含む）を DSM 上に、DSM がない場合は一定の地面の高さに投影したものです。属性：ラベル、写真のパス、有効かどうか、対地高度（m）、天底からの視線角（度）、撮影範囲についてはその面積（m²）と、縁全体が地面のデータに届いたかどうか（complete。DSM が途切れる所では、撮影範囲はカメラ直下の地面の高さの平面上に続きます）。地面と同じ高さかそれより下にあるカメラには撮影範囲がなく、その名前がログに示されます。

ローリングシャッター補正を使った Metashape プロジェクト：各写真は画像の行ごとに 1 つの姿勢を持ちます（読み出し中に Metashape が推定した動き）。撮影範囲は、他のすべての投影と同様にこれを使用し、適用された場合はログに示されます。

出力は、出力の座標参照系（CRS）が選択されていればその CRS、なければ DSM の CRS、なければ地図の CRS、なければ写真測量プロジェクトの CRS で作成されます（どれを使ったかはログに示されます）。*_wkt.prj のない Pix4D の params フォルダには、プロジェクトの CRS が必要です。ODM プロジェクトは ODM の CRS（そのオルソフォトと DSM の CRS）を使用します。ODM を伴わない OpenSfM データセットは、プロジェクトの CRS が設定されていなければ、基準点の WGS 84 / UTM ゾーンを使用します。DSM の高さまたは地面の高さは、プロジェクトの高さ基準で指定する必要があります（地理座標系の Metashape チャンクでは楕円体高、ODM ではその DSM の高さ）。</translation>
    </message>
    <message>
      <source>Output CRS</source>
      <translation>出力の座標参照系</translation>
    </message>
    <message>
      <source>Default: the DSM's, else the map's, else the photogrammetry project's</source>
      <translation>既定：DSM のもの、なければ地図のもの、なければ写真測量プロジェクトのもの</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF) for the footprints</source>
      <translation>撮影範囲用の DSM（GeoTIFF）</translation>
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
      <source>the output CRS chosen</source>
      <translation>選択された出力の CRS</translation>
    </message>
    <message>
      <source>the DSM's CRS</source>
      <translation>DSM の CRS</translation>
    </message>
    <message>
      <source>the map's CRS</source>
      <translation>地図の CRS</translation>
    </message>
    <message>
      <source>{n} camera(s) have no DSM right under them: their height above ground is taken from the DSM where their photo sees the ground.</source>
      <translation>{n} 台のカメラは直下に DSM がありません。これらの対地高度は、写真に地面が写る範囲の DSM から求めます。</translation>
    </message>
    <message>
      <source>{n} camera(s) see no DSM at all: their height above ground is taken from the median ground under the other cameras.</source>
      <translation>{n} 台のカメラは DSM をまったく捉えていません。これらの対地高度は、他のカメラ直下の地面の中央値から求めます。</translation>
    </message>
    <message>
      <source>Ground height when no DSM is given</source>
      <translation>DSM がないときの地面の高さ</translation>
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
      <source>Camera footprints of {project}</source>
      <translation>{project} のカメラ撮影範囲</translation>
    </message>
    <message>
      <source>Cameras of {project}</source>
      <translation>{project} のカメラ</translation>
    </message>
    <message>
      <source>Outputs in {crs} (the photogrammetry project's CRS).</source>
      <translation>出力は {crs}（写真測量プロジェクトの CRS）です。</translation>
    </message>
    <message>
      <source>{n} cameras and {f} footprints written.</source>
      <translation>カメラ {n} 台と撮影範囲 {f} 件を書き出しました。</translation>
    </message>
    <message>
      <source>The project is in a local coordinate system ({name}): the outputs will not line up with map layers.</source>
      <translation>プロジェクトはローカル座標系（{name}）です。出力は地図のレイヤと重なりません。</translation>
    </message>
    <message>
      <source>{n} camera(s) are at or below the ground, so they have no footprint: {names}. Check the ground height or the DSM and its vertical reference.</source>
      <translation>{n} 台のカメラが地面と同じ高さかそれより下にあるため、撮影範囲がありません：{names}。地面の高さ、または DSM とその高さ基準を確認してください。</translation>
    </message>
    <message>
      <source>{n} footprint(s) reach beyond the DSM's data: there they continue on a plane at the ground height under the camera (attribute complete = false).</source>
      <translation>{n} 件の撮影範囲が DSM のデータ範囲を超えています。その部分はカメラ直下の地面の高さの平面上に続きます（属性 complete = false）。</translation>
    </message>
    <message>
      <source>Outputs in {crs} ({why}).</source>
      <translation>出力は {crs}（{why}）です。</translation>
    </message>
    <message>
      <source>Create demo survey</source>
      <translation>デモ空撮データを作成</translation>
    </message>
    <message>
      <source>Demo data</source>
      <translation>デモデータ</translation>
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
      <translation>既知の正解を持つ、小さいながら完全な合成ドローン空撮データを書き出します。何もダウンロードせずに、EasyIDP のすべてのツールをすぐに試せます。空撮データは 40 区画からなる 60 m × 40 m の圃場です（UTM 54N）：
- オルソモザイク（1 cm）、DSM（2 cm）、区画（GeoPackage と GeoJSON、フィールド plot_id）
- 色付きの点群（LAZ と PLY）
- 往復飛行で撮影し、カメラモデルでレンダリングした 36 枚の元画像
- 同じ飛行の Agisoft Metashape プロジェクト、Pix4D プロジェクト、OpenDroneMap プロジェクト（odm/、opensfm/ のファイル付き）
- 4 枚の写真への LabelMe アノテーション
- truth.json：既知の地上点が各写真のどこにあるか

同じシードからは同じファイルが作られます。「小」は数秒で完了し、「中」は写真が大きくなります。

圃場（詳細）：雑然（既定）は実際の圃場にあるものを与えます：周縁の草、区画内外の雑草、生育むら、欠株区間、空の区画と倒伏区画、影、土の色の勾配、斜めの視点で条間の土を隠すほど高く密な作物列、通路のない区画のブロック。整然は以前の版の圃場です：裸地に細い列だけ。

生育シーズン（高度な設定）：N 個の日付を指定すると、作物が既知の曲線に沿って生育する間に同じ圃場を N 日飛行したデータも season/ に作成します：日付ごとのオルソモザイク、DSM、点群、裸地の DSM、品種付きの区画、surveys.csv（「シーズンを通した区画の形質」用の表）、season_truth.json（区画と日付ごとの高さと被覆）。</translation>
    </message>
    <message>
      <source>Random seed</source>
      <translation>乱数シード</translation>
    </message>
    <message>
      <source>Field</source>
      <translation>圃場</translation>
    </message>
    <message>
      <source>Growth season: dates flown (0: none)</source>
      <translation>生育シーズン：飛行日数（0：なし）</translation>
    </message>
    <message>
      <source>Output folder</source>
      <translation>出力フォルダ</translation>
    </message>
    <message>
      <source>Size</source>
      <translation>サイズ</translation>
    </message>
    <message>
      <source>Season survey table (surveys.csv)</source>
      <translation>シーズンの空撮一覧表（surveys.csv）</translation>
    </message>
    <message>
      <source>Orthomosaic</source>
      <translation>オルソモザイク</translation>
    </message>
    <message>
      <source>Plots</source>
      <translation>区画</translation>
    </message>
    <message>
      <source>Point cloud (LAZ)</source>
      <translation>点群（LAZ）</translation>
    </message>
    <message>
      <source>Metashape project</source>
      <translation>Metashape プロジェクト</translation>
    </message>
    <message>
      <source>Pix4D project</source>
      <translation>Pix4D プロジェクト</translation>
    </message>
    <message>
      <source>OpenDroneMap project</source>
      <translation>OpenDroneMap プロジェクト</translation>
    </message>
    <message>
      <source>OPF project (project.opf, PIX4Dmatic)</source>
      <translation>OPF プロジェクト（project.opf、PIX4Dmatic）</translation>
    </message>
    <message>
      <source>Truth file</source>
      <translation>正解ファイル</translation>
    </message>
    <message>
      <source>Demo survey</source>
      <translation>デモ空撮データ</translation>
    </message>
    <message>
      <source>messy (weeds, margin grass, tall rows, gaps, …)</source>
      <translation>雑然（雑草、周縁の草、高い作物列、欠株…）</translation>
    </message>
    <message>
      <source>tidy (narrow rows on bare soil)</source>
      <translation>整然（裸地に細い列）</translation>
    </message>
    <message>
      <source>Writing a {size} demo survey (seed {seed}, {field} field) into {folder}</source>
      <translation>{size} のデモ調査（シード {seed}、{field} の圃場）を {folder} に書き込み中</translation>
    </message>
    <message>
      <source>Demo survey written in {seconds:.1f} s: {n_photos} photos, {n_plot_ids} plots, {dates} season dates, in {folder}.</source>
      <translation>デモ空撮データを {folder} に書き出しました（{seconds:.1f} s）：写真 {n_photos} 枚、区画 {n_plot_ids} 個、シーズンの日付 {dates} 件。</translation>
    </message>
    <message>
      <source>small (800 × 600 photos)</source>
      <translation>小（写真 800 × 600）</translation>
    </message>
    <message>
      <source>medium (1600 × 1200 photos)</source>
      <translation>中（写真 1600 × 1200）</translation>
    </message>
    <message>
      <source>Demo plots</source>
      <translation>デモの区画</translation>
    </message>
    <message>
      <source>Demo orthomosaic</source>
      <translation>デモのオルソモザイク</translation>
    </message>
    <message>
      <source>Demo DSM</source>
      <translation>デモの DSM</translation>
    </message>
    <message>
      <source>Growth season: {n} dates in {f}</source>
      <translation>生育シーズン：{f} に {n} 日分</translation>
    </message>
    <message>
      <source>Create plot grid</source>
      <translation>プロットグリッドを作成</translation>
    </message>
    <message>
      <source>ROIs</source>
      <translation>ROI</translation>
    </message>
    <message>
      <source>Makes the plot polygons of a trial from its field layout: rows (ranges) × columns (passes) of plots, in blocks, numbered and joined to the field book.

Anchor: four corner points of the field in any order (they are sorted clockwise from the upper-left corner, the one whose edge to the next points closest to east; the log says the order used), a field-boundary polygon (its minimum-area rectangle), or an origin (the upper-left corner) and the bearing of the top edge (90 = east). Columns are counted along the top edge (x), rows down the left edge (y).

Layout, per axis: plot size, gap between plots (or the spacing, centre to centre), blocks and the gap between blocks. With corners or a boundary, a size or gap left empty is solved so that the plots fill the field. A negative buffer shrinks every plot on each side (a positive one grows it); plots stay rectangles.

Numbering: row by row, column by column or serpentine, from any corner, from the start id; the name pattern takes {plot_no}, {row}, {col}, {block}, {block_row}, {block_col}, {row_letter}, {range} and {pass}, e.g. {block}-{row:02d}-{col:02d}.

Field book: a table (e.g. a CSV layer) joined by plot id, plot number, or row and column; rows that match no plot and plots without a row are listed in the log.

The CRS must be projected in metres: a geographic CRS is refused with the UTM zone to use. Corners that are not a rectangle, and plots that would overlap, are refused with the amount.</source>
      <translation>圃場のレイアウトから試験のプロットポリゴンを作成します：ブロックに分かれた行（レンジ）× 列（パス）のプロットに番号を付け、フィールドブックを結合します。

アンカー：圃場の四隅の点（順序は任意。左上の角、すなわち次の角への辺が最も東に近い角から時計回りに並べ替え、使った順序をログに示します）、圃場境界ポリゴン（その最小面積外接矩形）、または原点（左上の角）と上辺の方位角（90 = 東）。列は上辺に沿って（x）、行は左辺に沿って下へ（y）数えます。

レイアウト（軸ごと）：プロットサイズ、プロット間の間隔（または中心間距離）、ブロック数とブロック間の間隔。四隅または境界を使う場合、空欄のサイズや間隔はプロットが圃場を埋めるように求められます。負のバッファは各プロットを各辺で縮め（正の値は広げ）、プロットは矩形のままです。

番号付け：行ごと、列ごと、または蛇行順に、任意の角から、開始番号から。名前のパターンには {plot_no}、{row}、{col}、{block}、{block_row}、{block_col}、{row_letter}、{range}、{pass} を使えます（例：{block}-{row:02d}-{col:02d}）。

フィールドブック：表（例：CSV レイヤ）をプロット ID、プロット番号、または行と列で結合します。どのプロットにも一致しない行と、行のないプロットはログに列挙されます。

CRS はメートル単位の投影座標系でなければなりません：地理座標系は使うべき UTM ゾーンを示して拒否されます。矩形にならない四隅や重なるプロットは、そのずれの量を示して拒否されます。</translation>
    </message>
    <message>
      <source>Four corner points (any order)</source>
      <translation>四隅の点（順序は任意）</translation>
    </message>
    <message>
      <source>Field boundary polygon (its minimum-area rectangle)</source>
      <translation>圃場境界ポリゴン（その最小面積外接矩形）</translation>
    </message>
    <message>
      <source>Origin point (upper-left corner) and bearing</source>
      <translation>原点（左上の角）と方位角</translation>
    </message>
    <message>
      <source>Row by row</source>
      <translation>行ごと</translation>
    </message>
    <message>
      <source>Serpentine rows (back and forth)</source>
      <translation>蛇行（行を往復）</translation>
    </message>
    <message>
      <source>Column by column</source>
      <translation>列ごと</translation>
    </message>
    <message>
      <source>Serpentine columns</source>
      <translation>蛇行（列を往復）</translation>
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
      <translation>プロット ID（名前）</translation>
    </message>
    <message>
      <source>Plot number</source>
      <translation>プロット番号</translation>
    </message>
    <message>
      <source>Row and column</source>
      <translation>行と列</translation>
    </message>
    <message>
      <source>How far the given corners may be from a rectangle</source>
      <translation>与えた四隅が長方形からずれてよい距離</translation>
    </message>
    <message>
      <source>Anchor</source>
      <translation>アンカー</translation>
    </message>
    <message>
      <source>Field corners (4 points)</source>
      <translation>圃場の四隅（4 点）</translation>
    </message>
    <message>
      <source>Field boundary (a polygon)</source>
      <translation>圃場の境界（ポリゴン）</translation>
    </message>
    <message>
      <source>Origin (upper-left corner of the field)</source>
      <translation>原点（圃場の左上の角）</translation>
    </message>
    <message>
      <source>Rows (ranges)</source>
      <translation>行数（レンジ）</translation>
    </message>
    <message>
      <source>Columns (passes)</source>
      <translation>列数（パス）</translation>
    </message>
    <message>
      <source>Plot size along a row (m; empty: fill the field)</source>
      <translation>行方向のプロットサイズ（m。空欄：圃場を埋める）</translation>
    </message>
    <message>
      <source>Plot size down a column (m; empty: fill the field)</source>
      <translation>列方向のプロットサイズ（m。空欄：圃場を埋める）</translation>
    </message>
    <message>
      <source>Gap between columns of plots (m; empty: solved)</source>
      <translation>プロット列の間隔（m。空欄：求める）</translation>
    </message>
    <message>
      <source>Alley between rows of plots (m; empty: solved)</source>
      <translation>プロット行の間の通路（m。空欄：求める）</translation>
    </message>
    <message>
      <source>Column spacing, centre to centre (m; not the gap)</source>
      <translation>列の間隔、中心間（m。すき間ではない）</translation>
    </message>
    <message>
      <source>Row spacing, centre to centre (m; not the alley)</source>
      <translation>行の間隔、中心間（m。通路ではない）</translation>
    </message>
    <message>
      <source>Blocks along a row</source>
      <translation>行方向のブロック数</translation>
    </message>
    <message>
      <source>Blocks down a column</source>
      <translation>列方向のブロック数</translation>
    </message>
    <message>
      <source>Gap between blocks along a row (m; empty: the plot gap)</source>
      <translation>行方向のブロック間隔（m。空欄：プロット間隔）</translation>
    </message>
    <message>
      <source>Gap between blocks down a column (m; empty: the alley)</source>
      <translation>列方向のブロック間隔（m。空欄：通路）</translation>
    </message>
    <message>
      <source>Numbering order</source>
      <translation>番号の順序</translation>
    </message>
    <message>
      <source>Numbering starts at</source>
      <translation>番号の開始位置</translation>
    </message>
    <message>
      <source>Start id (first plot number)</source>
      <translation>開始番号（最初のプロットの番号）</translation>
    </message>
    <message>
      <source>Name pattern</source>
      <translation>名前のパターン</translation>
    </message>
    <message>
      <source>Field book (a table, e.g. a CSV layer)</source>
      <translation>フィールドブック（表、例：CSV レイヤ）</translation>
    </message>
    <message>
      <source>Join the field book by</source>
      <translation>フィールドブックの結合キー</translation>
    </message>
    <message>
      <source>Field-book column of the plot id or number</source>
      <translation>フィールドブックの区画 ID または番号の列</translation>
    </message>
    <message>
      <source>Field-book column of the row (default: row)</source>
      <translation>フィールドブックの行の列（既定：row）</translation>
    </message>
    <message>
      <source>Field-book column of the column (default: col)</source>
      <translation>フィールドブックの列番号の列（既定：col）</translation>
    </message>
    <message>
      <source>Corner tolerance (m)</source>
      <translation>四隅の許容誤差（m）</translation>
    </message>
    <message>
      <source>Output CRS (projected, in metres; default: the anchor's)</source>
      <translation>出力 CRS（メートル単位の投影座標系。既定：アンカーの CRS）</translation>
    </message>
    <message>
      <source>Plot grid</source>
      <translation>プロットグリッド</translation>
    </message>
    <message>
      <source>Bearing of the top edge (degrees clockwise from north)</source>
      <translation>上辺の方位角（北から時計回りの度）</translation>
    </message>
    <message>
      <source>Buffer (m; negative shrinks every plot on each side)</source>
      <translation>バッファ（m。負の値は各プロットを各辺で縮める）</translation>
    </message>
    <message>
      <source>Origin: give the upper-left corner of the field (or choose another anchor).</source>
      <translation>原点：圃場の左上の角を指定してください（または別のアンカーを選んでください）。</translation>
    </message>
    <message>
      <source>Plot grid {rows} × {cols}</source>
      <translation>プロットグリッド {rows} × {cols}</translation>
    </message>
    <message>
      <source>{n} plots in {crs}.</source>
      <translation>{n} 個のプロット（{crs}）。</translation>
    </message>
    <message>
      <source>Field corners: give a point layer with the four corners of the field (or choose another anchor).</source>
      <translation>圃場の四隅：圃場の四隅を含むポイントレイヤを指定してください（または別のアンカーを選んでください）。</translation>
    </message>
    <message>
      <source>Field boundary: give a polygon layer with the field's outline (or choose another anchor).</source>
      <translation>圃場の境界：圃場の輪郭を含むポリゴンレイヤを指定してください（または別のアンカーを選んでください）。</translation>
    </message>
    <message>
      <source>Field book '{name}': {n} columns joined ({fields}).</source>
      <translation>フィールドブック「{name}」：{n} 列を結合しました（{fields}）。</translation>
    </message>
    <message>
      <source>Field corners: the layer '{layer}' has {n} points; exactly four are needed, one per corner of the field.</source>
      <translation>圃場の四隅：レイヤ「{layer}」には {n} 個の点があります。角ごとに 1 点、ちょうど 4 点が必要です。</translation>
    </message>
    <message>
      <source>Field boundary: the layer '{layer}' has no polygon.</source>
      <translation>圃場の境界：レイヤ「{layer}」にポリゴンがありません。</translation>
    </message>
    <message>
      <source>Origin '{value}' has no CRS: type it with its CRS in square brackets, e.g. '320000.0,3956100.0 [EPSG:32654]', or set the output CRS (the origin is then taken in it).</source>
      <translation>原点 '{value}' に座標参照系がありません：角括弧で座標参照系を付けて入力してください（例：'320000.0,3956100.0 [EPSG:32654]'）。または出力の座標参照系を設定してください（原点はその座標参照系とみなされます）。</translation>
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
      <translation>各 ROI（区画、樹木、植物のポリゴン）を点群（.las、.laz または .ply。例：Pix4D や Metashape の高密度点群）から切り出し、出力フォルダに ROI ごとに 1 ファイルとして保存します。ファイル名は名前フィールドに基づきます（ファイル名に使える一意の名前に変換されます）。

点の x, y がポリゴン内にあり（穴とマルチパートポリゴンも考慮）、Z 範囲が設定されている場合はその Z が範囲内にあるとき、その点は ROI に属します（高度な設定：例えば地面より下や樹冠より上のノイズを除くため）。重なり合う ROI の内側にある点は、それぞれの ROI に含まれます。点群は 1 回だけ読み込まれ、各点は近くの ROI に対してのみ判定されるため、大きな点群上の数千の ROI でも高速です。

すべての点属性（色、強度、分類、リターン、GPS 時刻、法線、追加次元）が正確な座標とともに保持されます。LAS/LAZ ファイルは CRS を持ちますが、PLY ファイルは持たないため、「点群の座標参照系」を指定してください（CRS のない LAS ファイルでも同様です）。別の CRS の ROI は点群の CRS に再投影されます。

点群の範囲外の ROI はログに名前が示され、スキップされます。点群の上にあっても点を含まない ROI は報告され、「点のない ROI にも空のファイルを書き出す」がオンでない限りファイルは作成されません。切り出した LAS/LAZ ファイルは、この QGIS が点群を表示できる場合（PDAL プロバイダ）、地図に読み込まれます。</translation>
    </message>
    <message>
      <source>Same as input</source>
      <translation>入力と同じ</translation>
    </message>
    <message>
      <source>LAZ (compressed LAS)</source>
      <translation>LAZ（圧縮 LAS）</translation>
    </message>
    <message>
      <source>Index of the crops (optional): the ROIs with the file ('crop_file'), the number of points ('points') and the outcome ('crop_status') of each. 'Open the crops in the map too' (off by default) opens up to 100 LAS/LAZ crops in one collapsed group below the ROI layer, where this QGIS can display point clouds (PDAL provider); a larger run opens the index only.</source>
      <translation>切り出しの索引（任意）：各 ROI とそのファイル（'crop_file'）、点数（'points'）、結果（'crop_status'）。「切り出しも地図で開く」（既定はオフ）をオンにすると、この QGIS が点群を表示できる場合（PDAL プロバイダ）、最大 100 個の LAS/LAZ の切り出しを ROI レイヤの下の折りたたんだグループに開きます。それより大きな実行では索引だけを開きます。</translation>
    </message>
    <message>
      <source>Write empty files for ROIs without any point</source>
      <translation>点のない ROI にも空のファイルを書き出す</translation>
    </message>
    <message>
      <source>Index of the crops</source>
      <translation>切り出しのインデックス</translation>
    </message>
    <message>
      <source>Open the crops in the map too</source>
      <translation>切り出しも地図で開く</translation>
    </message>
    <message>
      <source>Index of the point cloud crops</source>
      <translation>点群の切り出しのインデックス</translation>
    </message>
    <message>
      <source>Output format</source>
      <translation>出力形式</translation>
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
      <translation>切り出した点群は地図に読み込まれません：この QGIS には点群プロバイダ（PDAL）がありません。出力フォルダから開いてください（例：CloudCompare）。</translation>
    </message>
    <message>
      <source>PLY crops are not loaded into the map; open them from the output folder.</source>
      <translation>PLY の切り出しは地図に読み込まれません。出力フォルダから開いてください。</translation>
    </message>
    <message>
      <source>Cropping {n_rois} ROIs into {folder}</source>
      <translation>{n_rois} 個の ROI を {folder} に切り出しています</translation>
    </message>
    <message>
      <source>Point cloud crops of {cloud} ({n})</source>
      <translation>{cloud} の点群の切り出し（{n}）</translation>
    </message>
    <message>
      <source>{cropped} ROIs cropped ({points:,} points), {n_empty} without points, {n_missed} outside the cloud.</source>
      <translation>{cropped} 個の ROI を切り出しました（{points:,} 点）。点のない ROI は {n_empty} 個、点群の範囲外の ROI は {n_missed} 個です。</translation>
    </message>
    <message>
      <source>None of the {n_items} ROIs overlaps the point cloud: check that the ROIs and the cloud are in the right CRS (set 'Point cloud CRS' if the file has none or a wrong one).</source>
      <translation>{n_items} 個の ROI のいずれも点群と重なりません。ROI と点群の CRS が正しいか確認してください（ファイルに CRS がないか誤っている場合は「点群の座標参照系」を設定してください）。</translation>
    </message>
    <message>
      <source>Crop raster by ROIs</source>
      <translation>ROI でラスタを切り出し</translation>
    </message>
    <message>
      <source>Cuts every ROI (plot, tree, plant polygon) out of a GeoTIFF raster: an orthomosaic (DOM), a surface model (DSM) or a multispectral map, into one GeoTIFF per ROI in the output folder, named after the name field (made safe for file names and unique).

The raster is read in a single pass, each tile or strip once, so thousands of ROIs on rasters larger than memory are fast. Crops keep the raster's pixel grid, CRS and data type. Pixels outside the ROI are masked: RGB gets an alpha band, RGBA its alpha combined, DSM and multispectral get nodata (the raster's own, or -32767 for floating point and the type's extreme for integers when it has none). A pixel belongs to an ROI when its centre is inside (GDAL's rule); 'All touched' takes every pixel the ROI touches. Holes and multipart polygons are honoured. ROIs in another CRS are reprojected; ROIs outside the raster are reported and skipped.</source>
      <translation>各 ROI（区画、樹木、植物のポリゴン）を GeoTIFF ラスタ（オルソモザイク（DOM）、数値表層モデル（DSM）、またはマルチスペクトルマップ）から切り出し、出力フォルダに ROI ごとに 1 つの GeoTIFF として保存します。ファイル名は名前フィールドに基づきます（ファイル名に使える一意の名前に変換されます）。

ラスタは 1 回のパスで、各タイルまたはストリップを 1 度だけ読み込むため、メモリより大きいラスタ上の数千の ROI でも高速です。切り出しはラスタのピクセルグリッド、CRS、データ型を保持します。ROI 外のピクセルはマスクされます：RGB にはアルファバンドが追加され、RGBA ではアルファが合成され、DSM とマルチスペクトルには NoData 値が設定されます（ラスタ自身の値、ない場合は浮動小数点では -32767、整数では型の極値）。ピクセルの中心が ROI 内にあるとき、そのピクセルは ROI に属します（GDAL の規則）。「接触する全ピクセル」では、ROI が触れるすべてのピクセルが含まれます。穴とマルチパートポリゴンも考慮されます。別の CRS の ROI は再投影されます。ラスタの範囲外の ROI は報告され、スキップされます。</translation>
    </message>
    <message>
      <source>Index of the crops (optional): the ROIs with the file of each ('crop_file', empty for a skipped ROI) and 'crop_status'. 'Open the crops in the map too' (off by default) opens up to 100 crops in one collapsed group below the ROI layer; a larger run opens the index only.</source>
      <translation>切り出しの索引（任意）：各 ROI とそのファイル（'crop_file'。スキップした ROI では空）と 'crop_status'。「切り出しも地図で開く」（既定はオフ）をオンにすると、最大 100 個の切り出しを ROI レイヤの下の折りたたんだグループに開きます。それより大きな実行では索引だけを開きます。</translation>
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
      <source>Cropping {n_rois} ROIs out of {raster} into {folder}</source>
      <translation>{n_rois} 個の ROI を {raster} から {folder} に切り出しています</translation>
    </message>
    <message>
      <source>Crops of {raster} ({n})</source>
      <translation>{raster} の切り出し（{n}）</translation>
    </message>
    <message>
      <source>{n_files} GeoTIFFs written, {n_skipped} ROIs skipped.</source>
      <translation>{n_files} 個の GeoTIFF を書き出し、{n_skipped} 個の ROI をスキップしました。</translation>
    </message>
    <message>
      <source>ROI '{name}' skipped: {reason}</source>
      <translation>ROI '{name}' をスキップしました：{reason}</translation>
    </message>
    <message>
      <source>Export a training set</source>
      <translation>学習データセットを書き出す</translation>
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
      <translation>地図上で一度だけラベル付けしたオブジェクト（ポリゴン、または半径付きのポイント）を、生写真上の深層学習用データセットに変換します：COCO インスタンス（ポリゴンとボックス）、YOLO のセグメント／検出ラベルとその data.yaml、LabelMe ファイル。

各オブジェクトは、それが写るすべての写真に逆投影されます（高さは DSM から、レンズ歪みを含み、DSM で遮蔽を判定し、「ROI の逆投影」と同じく写真を順位付け）。オブジェクトは、少なくとも最小可視割合がフレーム内にあり、自分以外の何にも隠されていない写真でラベル付けされます（畝間の土など、自分の群落が隠す部分は数えません）。輪郭はフレームで切り取られます（隠れた部分は切り取りません）。オブジェクトごとの最良写真：上位 k 枚のみ残します（0 = すべて）。

タイル：タイルサイズを指定すると、写真はそのサイズ（ピクセル）のタイルに重なりを持たせて分割されます。輪郭は各タイルで正確に切り取られ、オブジェクトの最小可視割合より小さい部分は捨てられます。指定しなければ写真全体をコピーします。

デコードできない写真（途中で切れたもの、画像でないもの）はログに名前を示し、そのラベルとともに除外します。

画像の値：保存された値のまま（既定：写真をコピーし、タイルは PNG）、°C の温度、または反射率。「元画像からの区画統計」と同じです。PNG と JPEG はこれらの値を保持できないため、その場合は写真全体もタイルもすべての画像が float32 TIFF（NAME.tif、ラベルはこれを参照）になり、単位を GDAL メタデータに記録し、飽和または読み取れない画素は NaN になります。そのような値を持たない写真はラベルとともに除外されます。ネットワークはどちらの画像でも学習できます。

分割：画像は丸ごと学習または検証に割り当てられ、除外される画像はありません。圃場の領域（領域サイズの正方形セル、DSM の地図単位。画像はそのオブジェクトの多くが属する領域に従います）ごと、または写真ごとに分けます。ログには各セットの画像数とラベル数を示し、検証セットが空のとき、または指定割合の半分に満たないときは警告します。両方のセットの画像に写るオブジェクトは数えて示します。

タイル：1 枚の写真が 4096 個を超えるタイルに分かれるタイルサイズは拒否します。

出力フォルダー：images/{train,val}、labels/{train,val} と data.yaml（YOLO セグメント）、yolo_detect/（YOLO 検出）、coco/instances_{train,val}.json、labelme/{train,val}、training_set.json（件数、規則、書き込んだファイルの一覧）。フォルダーにはデータセットだけを置きます：それ以外のファイルがあれば一覧を示して拒否します。古いデータセットは「既存のファイルを上書き」がオンのときだけ置き換え、その training_set.json に載っているファイルだけを削除します。</translation>
    </message>
    <message>
      <source>Random seed of the split</source>
      <translation>分割の乱数シード</translation>
    </message>
    <message>
      <source>Values of the images</source>
      <translation>画像の値</translation>
    </message>
    <message>
      <source>Labelled objects (polygons or points)</source>
      <translation>ラベル付きオブジェクト（ポリゴンまたはポイント）</translation>
    </message>
    <message>
      <source>Class field</source>
      <translation>クラスフィールド</translation>
    </message>
    <message>
      <source>Instance id field (default: feature id)</source>
      <translation>インスタンス ID フィールド（既定：地物 ID）</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF)</source>
      <translation>DSM（GeoTIFF）</translation>
    </message>
    <message>
      <source>Best photos per object (0 = all)</source>
      <translation>オブジェクトごとの最良写真数（0 = すべて）</translation>
    </message>
    <message>
      <source>Tile size (pixels; 0 = whole photos)</source>
      <translation>タイルサイズ（ピクセル、0 = 写真全体）</translation>
    </message>
    <message>
      <source>Tile overlap (pixels)</source>
      <translation>タイルの重なり（ピクセル）</translation>
    </message>
    <message>
      <source>Train/validation split</source>
      <translation>学習／検証の分割</translation>
    </message>
    <message>
      <source>Training set folder</source>
      <translation>学習データセットのフォルダー</translation>
    </message>
    <message>
      <source>Labelled objects: no layer given, or it could not be loaded.</source>
      <translation>ラベル付きオブジェクト：レイヤーが指定されていないか、読み込めません。</translation>
    </message>
    <message>
      <source>EasyIDP</source>
      <translation>EasyIDP</translation>
    </message>
    <message>
      <source>Labelled objects</source>
      <translation>ラベル付きオブジェクト</translation>
    </message>
    <message>
      <source>Radius of the disc around labelled points (map units)</source>
      <translation>ラベル付きポイントの周りの円の半径（地図単位）</translation>
    </message>
    <message>
      <source>Minimum visible, unoccluded share of an object</source>
      <translation>オブジェクトの見えていて遮られていない最小割合</translation>
    </message>
    <message>
      <source>Validation fraction</source>
      <translation>検証データの割合</translation>
    </message>
    <message>
      <source>Region size for the split (map units of the DSM)</source>
      <translation>分割に使う領域の大きさ（DSM の地図単位）</translation>
    </message>
    <message>
      <source>Training set: {warning}</source>
      <translation>学習データセット：{warning}</translation>
    </message>
    <message>
      <source>Labelled objects: polygons or points are needed, not lines.</source>
      <translation>ラベル付きオブジェクト：ラインではなくポリゴンかポイントが必要です。</translation>
    </message>
    <message>
      <source>By field region</source>
      <translation>圃場の領域ごと</translation>
    </message>
    <message>
      <source>By photo</source>
      <translation>写真ごと</translation>
    </message>
    <message>
      <source>Object '{name}': {why}</source>
      <translation>オブジェクト '{name}'：{why}</translation>
    </message>
    <message>
      <source>Removed {n} file(s) of the older training set in the folder.</source>
      <translation>フォルダー内の古い学習データセットのファイル {n} 個を削除しました。</translation>
    </message>
    <message>
      <source>{split}: {images} images, {labels} labels of {objects} objects</source>
      <translation>{split}：画像 {images} 枚、{objects} 個のオブジェクトのラベル {labels} 個</translation>
    </message>
    <message>
      <source>Labelled points need a positive disc radius (map units).</source>
      <translation>ラベル付きポイントには正の円の半径（地図単位）が必要です。</translation>
    </message>
    <message>
      <source>Labelled objects: the layer has no field '{f}'.</source>
      <translation>ラベル付きオブジェクト：レイヤーにフィールド '{f}' がありません。</translation>
    </message>
    <message>
      <source>Labelled objects: object '{name}' has no class in the field '{f}'. Fill it or filter the layer.</source>
      <translation>ラベル付きオブジェクト：オブジェクト '{name}' のフィールド '{f}' にクラスがありません。入力するかレイヤーを絞り込んでください。</translation>
    </message>
    <message>
      <source>Fit plot grid to crop rows</source>
      <translation>グリッドを作物の条に合わせる</translation>
    </message>
    <message>
      <source>Moves a plot grid onto the crop that was really planted, as the orthomosaic shows it.

It tells the crop from weeds, margin grass and soil by its rows, not by greenness alone. From a vegetation index (ExG of an RGB orthomosaic, or NDVI of a multispectral one with its red and NIR bands) it finds the direction and spacing of the crop rows (the image's spectrum), then the grid's global rotation, spacing scale and shift from the plot block (all plots vote at once, so the field margins cannot pull it), then a per-plot shift, at most the bound, that centres each plot on its own rows: across them on the rows' positions (the median along each row, so that weeds and gaps do not pull it), along them on the row ends most of its rows agree on. Plots keep their size and shape. On the hard demo trial (margin grass, weeds, gaps, lodging; 3 seeds, 9 start grids up to 3°, 0.5 m and 3 % off) the fitted corners lie a median of 0.15–0.23 cm and at most 2.4 cm from the planted plots, and a correct grid moves by at most 0.93 cm.

Plots without rows (empty, bare soil), whose rows go on beyond their ends, or whose shift would exceed the bound are left in place: they keep the global correction only, with moved = 0 and the reason in fit_flag. Every plot gets shift_x, shift_y and shift_m (its own shift, m), fit_score (0–1: 1 when the plot's rows stop at its ends, 0 when they go on beyond them) and cover (its rows' strength over the median plot's). Features without a polygon are named in the log and written out unchanged.

The log gives the global correction and how many plots moved by more than the threshold. The orthomosaic is read in one pass by windows (any size; it is averaged to at most 16 million pixels), and the run can be cancelled. An orthomosaic with no vegetation under the plots is refused, and nothing is written. The output is in the orthomosaic's CRS, which must be projected in metres.</source>
      <translation>プロットグリッドを、オルソモザイクに写る実際に播種された作物の位置へ移動します。

緑の度合いだけでなく作物の条によって、作物を雑草・周縁の草・土壌と区別します。植生指数（RGB オルソモザイクの ExG、またはマルチスペクトルの赤と近赤外バンドによる NDVI）から、まず作物の条の方向と条間（画像のスペクトル）を求め、次にプロットの区画全体からグリッド全体の回転・間隔の倍率・移動を求め（すべてのプロットが同時に投票するので、圃場の周縁に引きずられません）、最後に上限以内のプロットごとの移動で、各プロットを自身の条の中心に合わせます：条に直交する向きは条の位置（各条に沿った中央値を使うので、雑草や欠株に引きずられません）で、条に沿う向きは多くの条が一致する条の両端で合わせます。プロットのサイズと形は変わりません。難しいデモ試験圃場（周縁の草、雑草、欠株、倒伏。3 つのシード、最大 3°・0.5 m・3 % ずれた 9 つの開始グリッド）では、当てはめた角は播種されたプロットから中央値 0.15–0.23 cm、最大 2.4 cm の位置に来て、正しいグリッドの移動は最大 0.93 cm です。

条のないプロット（空きプロット、裸地）、条がプロットの両端を越えて続くプロット、移動が上限を超えるプロットはその場に残されます：全体の補正だけを受け、moved = 0 で、理由は fit_flag に入ります。各プロットには shift_x、shift_y、shift_m（自身の移動量、m）、fit_score（0–1：プロットの条がその両端で終わるなら 1、両端を越えて続くなら 0）、cover（条の強さのプロット中央値に対する比）が付きます。ポリゴンのない地物はログに名前が出され、そのまま書き出されます。

ログには全体の補正と、しきい値より大きく移動したプロットの数が出ます。オルソモザイクはウィンドウごとに一度だけ読み込まれ（任意のサイズ。最大 1600 万画素に平均化）、実行はキャンセルできます。プロットの下に植生のないオルソモザイクは拒否され、何も書き出されません。出力はオルソモザイクの CRS で、メートル単位の投影座標系でなければなりません。</translation>
    </message>
    <message>
      <source>Automatic (ExG for an RGB orthomosaic)</source>
      <translation>自動（RGB オルソモザイクには ExG）</translation>
    </message>
    <message>
      <source>ExG (2G − R − B)/(R + G + B), RGB</source>
      <translation>ExG (2G − R − B)/(R + G + B)、RGB</translation>
    </message>
    <message>
      <source>NDVI (NIR − R)/(NIR + R), multispectral</source>
      <translation>NDVI (NIR − R)/(NIR + R)、マルチスペクトル</translation>
    </message>
    <message>
      <source>Name field</source>
      <translation>名前フィールド</translation>
    </message>
    <message>
      <source>The plots' names in labels and the log; default: plot_id, else the feature id</source>
      <translation>ラベルとログでの区画名。既定：plot_id、なければ地物 ID</translation>
    </message>
    <message>
      <source>Empty: 0.6 m + 9 % of the grid's half extent</source>
      <translation>空欄：0.6 m + グリッドの半幅の 9 %</translation>
    </message>
    <message>
      <source>Plot grid (polygons)</source>
      <translation>プロットグリッド（ポリゴン）</translation>
    </message>
    <message>
      <source>Orthomosaic (GeoTIFF)</source>
      <translation>オルソモザイク（GeoTIFF）</translation>
    </message>
    <message>
      <source>Vegetation index</source>
      <translation>植生指数</translation>
    </message>
    <message>
      <source>Red band (ExG, NDVI)</source>
      <translation>赤バンド（ExG、NDVI）</translation>
    </message>
    <message>
      <source>Green band (ExG)</source>
      <translation>緑バンド（ExG）</translation>
    </message>
    <message>
      <source>Blue band (ExG)</source>
      <translation>青バンド（ExG）</translation>
    </message>
    <message>
      <source>Near-infrared band (NDVI)</source>
      <translation>近赤外バンド（NDVI）</translation>
    </message>
    <message>
      <source>Search radius of the global correction (m)</source>
      <translation>全体補正の探索半径（m）</translation>
    </message>
    <message>
      <source>Fitted plot grid</source>
      <translation>合わせたプロットグリッド</translation>
    </message>
    <message>
      <source>Plot grid: the layer has no plots.</source>
      <translation>プロットグリッド：レイヤにプロットがありません。</translation>
    </message>
    <message>
      <source>Left in place (see fit_flag)</source>
      <translation>元の位置のまま（fit_flag を参照）</translation>
    </message>
    <message>
      <source>Fitted to the rows</source>
      <translation>条に合わせた</translation>
    </message>
    <message>
      <source>Largest per-plot shift (m)</source>
      <translation>プロットごとの最大移動量（m）</translation>
    </message>
    <message>
      <source>Report plots moved by more than (m)</source>
      <translation>この値より大きく移動したプロットを報告（m）</translation>
    </message>
    <message>
      <source>Bare below this share of the median plot's row strength</source>
      <translation>条の強さがプロットの中央値に対してこの割合未満なら裸地とする</translation>
    </message>
    <message>
      <source>Weak fit below this score</source>
      <translation>スコアがこの値未満なら適合が弱いとする</translation>
    </message>
    <message>
      <source>{grid}: fitted to {ortho}</source>
      <translation>{grid}：{ortho} に合わせた</translation>
    </message>
    <message>
      <source>Plot grid: {n} features have no polygon (NULL or empty geometry) and are skipped (written out unchanged, fit_flag '{flag}'): {names}.</source>
      <translation>プロットグリッド：{n} 個の地物にポリゴンがありません（NULL または空のジオメトリ）。スキップします（そのまま書き出し、fit_flag は '{flag}'）：{names}。</translation>
    </message>
    <message>
      <source>Plot grid: none of the {n} features has a polygon (all NULL or empty geometries).</source>
      <translation>プロットグリッド：{n} 個の地物のどれにもポリゴンがありません（すべて NULL または空のジオメトリ）。</translation>
    </message>
    <message>
      <source>Plot '{name}' left in place: {reason}.</source>
      <translation>プロット「{name}」はその場に残しました：{reason}。</translation>
    </message>
    <message>
      <source>… and {n} more plots left in place.</source>
      <translation>… ほかに {n} 個のプロットをその場に残しました。</translation>
    </message>
    <message>
      <source>Forward-project polygons</source>
      <translation>写真上のポリゴンを地図へ投影</translation>
    </message>
    <message>
      <source>Brings polygons drawn or detected on the raw photos (LabelMe, COCO, YOLO, or the photo-pixel layer written by Back-project ROIs) to the map, with their true position, area and perimeter: every vertex's pixel becomes a ray through the solved camera (lens distortion included) and its first hit on the DSM is the vertex on the map. Exact on any terrain and canopy (not a flat-ground homography).

Input, one of: a file (LabelMe .json, COCO .json, YOLO .txt); a folder (LabelMe .json files or YOLO .txt files, with classes.txt or data.yaml for class names); or a photo-pixel layer (x = column, y = −row, field 'photo'). Each image is matched to a photo of the project by file name; an image that is not in the project, or whose size differs from the camera's, is refused with its name. Detections on the tiles of a tiled training set (YOLO or LabelMe files named after the tiles) need its tile index (tiles.json): they are shifted back into their photo's pixels; COCO files of the set carry their tile windows themselves.

Edges are densified in the photo (a vertex every few pixels) so that long edges follow the surface. A vertex whose ray misses the DSM, leaves it or enters nodata is dropped and its polygon marked complete = false (and reported), never silently reshaped.

Merge: 'none' keeps one polygon per photo; 'union' merges the overlapping polygons of one label from several photos into one; 'best' keeps the best view (complete, highest score, most nadir); 'fuse' is for detections with scores (COCO results with the COCO images file, YOLO with confidence, LabelMe): duplicates in a photo are suppressed, the views of one object grouped by overlap and distance, and each object gets the outline most of its views agree on, its number of views, the photos that could have seen it (expected_views), mean and max score, its position and DSM height, and a confidence (mean score × views / expected views). Fields: photo, label, score, area_m2 and perimeter_m (planimetric, metres), views, complete, missing (vertices without a hit), and for 'fuse' expected_views, max_score and confidence. Output in the DSM's CRS, heights from the DSM.</source>
      <translation>元画像（撮影写真）上で描画または検出したポリゴン（LabelMe、COCO、YOLO、または「ROI を元画像へ逆投影」が書き出す写真ピクセルのレイヤ）を、正しい位置、面積、周長で地図へ投影します：各頂点のピクセルは、解かれたカメラを通る光線（レンズ歪みを含む）となり、その光線が DSM と最初に交わる点が地図上の頂点になります。どのような地形や樹冠でも正確です（平坦な地面を仮定したホモグラフィではありません）。

入力は次のいずれか 1 つです：ファイル（LabelMe .json、COCO .json、YOLO .txt）、フォルダ（LabelMe .json ファイルまたは YOLO .txt ファイル。クラス名には classes.txt または data.yaml）、または写真ピクセルのレイヤ（x = 列、y = −行、フィールド 'photo'）。各画像はファイル名でプロジェクトの写真と照合されます。プロジェクトにない画像や、サイズがカメラと異なる画像は、その名前を示して拒否されます。タイル分割した学習データセットのタイル上の検出（タイル名の YOLO または LabelMe ファイル）には、そのタイル索引（tiles.json）が必要です。検出は元の写真のピクセル座標へ戻されます。このデータセットの COCO ファイルはタイルの範囲を自ら保持しています。

辺は写真上で高密度化され（数ピクセルごとに 1 頂点）、長い辺も地表に沿います。光線が DSM に当たらない、DSM の外に出る、または NoData 値に入る頂点は除外され、そのポリゴンには complete = false が設定されます（報告もされます）。黙って形が変えられることはありません。

統合：「なし」は写真ごとに 1 つのポリゴンを残します。「視点の和集合」は、複数の写真に写る同じラベルの重なり合うポリゴンを 1 つに統合します。「最良の視点」は最良の視点（complete、最高スコア、最も天底に近いもの）を残します。フィールド：photo、label、score、area_m2 と perimeter_m（平面上、メートル単位）、views、complete、missing（交点のない頂点）。出力は DSM の CRS で、高さは DSM から取得します。

「融合」（fuse）はスコア付きの検出（COCO 結果と COCO 画像ファイル、信頼度付き YOLO、LabelMe）向けです：写真内の重複を抑制し、同じオブジェクトの複数のビューを重なりと距離でまとめ、各オブジェクトに多数のビューが一致する輪郭、ビュー数、それを写し得た写真数（expected_views）、平均・最大スコア、位置と DSM 高さ、信頼度（平均スコア × ビュー数 / 期待ビュー数）を与えます。フィールド expected_views、max_score、confidence。</translation>
    </message>
    <message>
      <source>Give exactly one of the three annotation inputs: a file, a folder or a photo-pixel layer.</source>
      <translation>3 つのアノテーション入力（ファイル、フォルダ、写真ピクセルのレイヤ）のうち、ちょうど 1 つを指定してください。</translation>
    </message>
    <message>
      <source>Merge the same object seen in several photos</source>
      <translation>複数の写真に写る同じ物体を統合</translation>
    </message>
    <message>
      <source>COCO images file that a COCO results list refers to</source>
      <translation>COCO 結果リストが参照する COCO 画像ファイル</translation>
    </message>
    <message>
      <source>Tile index (tiles.json), for annotations on tiles</source>
      <translation>タイルの索引（tiles.json）：タイル上のアノテーション用</translation>
    </message>
    <message>
      <source>Densify edges: a vertex every … photo pixels (0: off)</source>
      <translation>辺の高密度化：… 写真ピクセルごとに 1 頂点（0：オフ）</translation>
    </message>
    <message>
      <source>Polygons on the map</source>
      <translation>地図上のポリゴン</translation>
    </message>
    <message>
      <source>Give exactly one input: an annotation file, a folder of annotation files, or a photo-pixel layer.</source>
      <translation>入力は 1 つだけ指定してください：アノテーションファイル、アノテーションファイルのフォルダ、または写真ピクセルのレイヤ。</translation>
    </message>
    <message>
      <source>Incomplete: a vertex found no DSM</source>
      <translation>不完全：DSM に当たらない頂点あり</translation>
    </message>
    <message>
      <source>Complete</source>
      <translation>完全</translation>
    </message>
    <message>
      <source>Annotations, 1 of 3: a LabelMe, COCO or YOLO file</source>
      <translation>アノテーション（3 つから 1 つ）：LabelMe、COCO、YOLO ファイル</translation>
    </message>
    <message>
      <source>Annotations, 2 of 3: a LabelMe or YOLO folder</source>
      <translation>アノテーション（3 つから 1 つ）：LabelMe か YOLO のフォルダ</translation>
    </message>
    <message>
      <source>Annotations, 3 of 3: a photo-pixel polygon layer</source>
      <translation>アノテーション（3 つから 1 つ）：写真ピクセルのポリゴンレイヤ</translation>
    </message>
    <message>
      <source>Layer coordinates: x = column, y = −row.</source>
      <translation>レイヤの座標：x = 列、y = −行。</translation>
    </message>
    <message>
      <source>{what} on the map (through {project} onto {dsm})</source>
      <translation>地図上の {what}（{project} を通して {dsm} へ投影）</translation>
    </message>
    <message>
      <source>{n} polygons from {p} photos written to the map ({i} incomplete).</source>
      <translation>{p} 枚の写真から {n} 個のポリゴンを地図に書き出しました（不完全：{i} 個）。</translation>
    </message>
    <message>
      <source>None (one polygon per photo)</source>
      <translation>なし（写真ごとに 1 ポリゴン）</translation>
    </message>
    <message>
      <source>Union of the views</source>
      <translation>視点の和集合</translation>
    </message>
    <message>
      <source>Best view</source>
      <translation>最良の視点</translation>
    </message>
    <message>
      <source>Fuse detections (NMS, consensus outline, confidence)</source>
      <translation>検出の融合（NMS、合意輪郭、信頼度）</translation>
    </message>
    <message>
      <source>{n} lines or points skipped: only polygons are forward-projected by this tool.</source>
      <translation>{n} 個のラインまたはポイントをスキップしました：このツールで地図へ投影するのはポリゴンのみです。</translation>
    </message>
    <message>
      <source>'{label}' is incomplete ({why}).</source>
      <translation>'{label}' は不完全です（{why}）。</translation>
    </message>
    <message>
      <source>Orthorectify ROIs</source>
      <translation>元画像から ROI をオルソ補正</translation>
    </message>
    <message>
      <source>Makes, for every ROI, a georeferenced image from a raw photo instead of the orthomosaic: sharper (no blending, ghosting or seamlines) and with true geometry. Each output pixel's ground point (its height from the DSM) is projected into the photo with the solved camera (lens distortion included) and the photo is sampled there (bilinear).

Photos: 'best' takes the best-scored photo of each ROI (the backward projection's score: visible share, view angle, resolution, distance from the centre); 'all' writes one image per photo that sees the ROI; 'named photo' uses the photo given. Pixel size: the GSD given (DSM CRS units), or 0 for the photo's native resolution at the ROI.

Output pixels outside the ROI, on DSM nodata, outside the photo, or hidden from the camera by the DSM (occlusion) are transparent (alpha 0).

Mask: 'occlusion mask' (the default) casts a ray from every output pixel's ground point to the camera and makes the pixel transparent where the DSM blocks it (a tree or a wall between them), so no pixel shows what stands in front of it; 'none' skips the rays and keeps every pixel the photo frames, as Orthority does (faster; hidden ground then shows the object that hides it).

One GeoTIFF per ROI (and photo, for 'all') in the output folder, in the DSM's CRS, with the photo's bands plus alpha. The photos are read from the paths stored in the project, or from the photos folder when given (matched by file name).

Values: as stored (the photo's bands and data type, the default), temperature in °C (FLIR radiometric JPEGs by the Planck curve, with the photo's object parameters unless given; temperature TIFFs by their preset or scale and offset) or reflectance (MicaSense and DJI multispectral band files), as in Plot statistics from photos. Temperature and reflectance images are float32 GeoTIFFs with the unit and what was applied in their GDAL metadata; pixels without a value, and those whose bilinear sample touches a saturated or unreadable photo pixel, are NaN (nodata, alpha 0).</source>
      <translation>各 ROI について、オルソモザイクではなく元画像（撮影写真）からジオリファレンス付きの画像を作成します：より鮮明で（ブレンド、ゴースト、シームラインがなく）、正しい幾何形状を持ちます。出力の各ピクセルの地上点（高さは DSM から取得）を、解かれたカメラ（レンズ歪みを含む）で写真に投影し、その位置で写真をサンプリングします（バイリニア）。

写真：「各 ROI の最良の写真」は、各 ROI で最もスコアの高い写真を使用します（逆投影のスコア：見える割合、視線角、解像度、中心からの距離）。「ROI が写るすべての写真」は、ROI が写る写真ごとに 1 枚の画像を書き出します。「指定した写真」は、指定された写真を使用します。ピクセルサイズ：指定した地上画素寸法（GSD）（DSM の CRS の単位）、または ROI における写真本来の解像度を使う場合は 0。

ROI の外、DSM の NoData 値の上、写真の外、または DSM によってカメラから隠れている（遮蔽）出力ピクセルは透明になります（アルファ 0）。

マスク：「遮蔽マスク」（既定）は、出力の各ピクセルの地上点からカメラへ光線を投げ、DSM がそれを遮る場所（間にある木や壁）のピクセルを透明にします。これにより、手前にあるものを写したピクセルは残りません。「なし」は光線を投げず、写真に写るすべてのピクセルを残します（Orthority と同じ動作）。より速くなりますが、隠れた地面にはそれを隠している物体が写ります。

出力フォルダに ROI ごと（「ROI が写るすべての写真」では写真ごと）に 1 つの GeoTIFF を、DSM の CRS で、写真のバンドとアルファを付けて書き出します。写真はプロジェクトに保存されたパスから読み込みます。元画像のフォルダを指定した場合はそこから読み込みます（ファイル名で照合）。

値：保存された値のまま（写真のバンドとデータ型、既定）、°C の温度（FLIR ラジオメトリック JPEG はプランク曲線で換算し、指定がなければ写真の対象パラメータを使用。温度 TIFF はプリセットまたはスケールとオフセットで換算）、または反射率（MicaSense と DJI のマルチスペクトルバンドファイル）。「元画像からの区画統計」と同じです。温度と反射率の画像は float32 GeoTIFF で、単位と適用した換算を GDAL メタデータに記録します。値のない画素と、双線形サンプリングが飽和または読み取れない写真画素に触れる画素は NaN（nodata、alpha 0）になります。</translation>
    </message>
    <message>
      <source>Index of the images (optional): one feature per image, the ROI with its file ('image_file'), photo, visible share and pixel size. 'Open the images in the map too' (off by default) opens up to 100 images in one collapsed group below the ROI layer; a larger run opens the index only.</source>
      <translation>画像の索引（任意）：画像ごとに 1 地物で、ROI とそのファイル（'image_file'）、写真、見える割合、画素サイズ。「画像も地図で開く」（既定はオフ）をオンにすると、最大 100 枚の画像を ROI レイヤの下の折りたたんだグループに開きます。それより大きな実行では索引だけを開きます。</translation>
    </message>
    <message>
      <source>Pixel size (DSM CRS units; 0: the photo's native resolution)</source>
      <translation>ピクセルサイズ（DSM の CRS の単位。0：写真本来の解像度）</translation>
    </message>
    <message>
      <source>Index of the images</source>
      <translation>画像のインデックス</translation>
    </message>
    <message>
      <source>Open the images in the map too</source>
      <translation>画像も地図で開く</translation>
    </message>
    <message>
      <source>Values</source>
      <translation>値</translation>
    </message>
    <message>
      <source>Folder of the raw photos (default: the paths in the project)</source>
      <translation>元画像のフォルダ（既定：プロジェクト内のパス）</translation>
    </message>
    <message>
      <source>Photos</source>
      <translation>写真</translation>
    </message>
    <message>
      <source>Photo label (for 'A named photo')</source>
      <translation>写真のラベル（「指定した写真」の場合）</translation>
    </message>
    <message>
      <source>Mask</source>
      <translation>マスク</translation>
    </message>
    <message>
      <source>Orthorectified ROI images</source>
      <translation>オルソ補正した ROI 画像</translation>
    </message>
    <message>
      <source>Number of images written</source>
      <translation>書き出した画像の数</translation>
    </message>
    <message>
      <source>{rois} from raw photos ({n})</source>
      <translation>元画像からの {rois}（{n}）</translation>
    </message>
    <message>
      <source>{n} orthorectified ROI images written to {folder}; {s} skipped.</source>
      <translation>オルソ補正した ROI 画像 {n} 枚を {folder} に書き出しました。スキップ：{s} 件。</translation>
    </message>
    <message>
      <source>Best photo of each ROI</source>
      <translation>各 ROI の最良の写真</translation>
    </message>
    <message>
      <source>Every photo that sees the ROI</source>
      <translation>ROI が写るすべての写真</translation>
    </message>
    <message>
      <source>A named photo</source>
      <translation>指定した写真</translation>
    </message>
    <message>
      <source>Occlusion mask (hide the ground the DSM hides from the camera)</source>
      <translation>遮蔽マスク（DSM によってカメラから隠れている地面を隠す）</translation>
    </message>
    <message>
      <source>None (every pixel the photo frames, as Orthority)</source>
      <translation>なし（写真に写るすべてのピクセル、Orthority と同じ）</translation>
    </message>
    <message>
      <source>{what}: no image ({why}).</source>
      <translation>{what}：画像なし（{why}）。</translation>
    </message>
    <message>
      <source>Plot statistics from photos</source>
      <translation>元画像からの区画統計</translation>
    </message>
    <message>
      <source>Measures every ROI (plot) in every raw photo that sees it, and gives each ROI one robust value across its views. Raw photos have no ghosting or seamlines and true colour from near-nadir views.

Inputs as Back-project ROIs: the ROI polygons, the photogrammetry project, the heights of the ROI vertices and a DSM; the backward projection runs here, unless its photo-pixel layer (the OUTPUT of Back-project ROIs) is given, which is then used as it is.

Per ROI and photo, the pixels whose centre is inside the ROI's polygon (clipped to the frame) give: per band the mean, median, standard deviation and chosen percentiles, in the photo's own values (8-bit, 16-bit or float; never converted to 8-bit); the vegetation indices ExG, ExGR, VARI, GLI (red, green, blue) and NDVI, NDRE (for multispectral photos, name the bands, e.g. 'blue,green,red,rededge,nir'); the canopy cover (share of pixels whose NDVI, else ExG, is at or above the threshold: the one given, or Otsu's over all views); the pixel count and the GSD. With a DSM, pixels whose line of sight meets the surface outside the ROI (hidden by a tree, a neighbour, a wall) are left out and their share is reported.

Across views, per ROI: the median of each statistic (score-weighted if asked), its MAD, minimum and maximum over the views used (visible share at least the minimum; the best ones by score when a maximum is set), their number, each view's deviation from its ROI's value and each ROI's largest (the disagreement; about 1 is typical for the field, several times more flags a shadow, wind, a bad pose). Oblique views see the sides of tall canopy, so cover and indices grow with the view angle: the default keeps the 3 best views.

Values: as stored (the photos' own numbers), temperature in °C (FLIR radiometric JPEGs of the Zenmuse XT/XT2, Vue Pro R, Duo Pro R and FLIR handhelds, converted by the Planck curve with the photo's constants and object parameters, each of which can be overridden; or temperature TIFFs with a stated scale and offset; DJI R-JPEGs must be converted with DJI's tool first) or reflectance (MicaSense and DJI multispectral band files, from their irradiance sensor). The band files of one capture are one view: each band is measured through its own camera, one row per ROI × capture with a column per band, and indices come from the band means and medians of the same ROI. Temperature and reflectance put the unit in the column names (temp_c_mean, nir_refl_median); saturated pixels are left out. Each view also gets its photo's acquisition time and the sun's zenith, azimuth and phase angle (sun–plot–camera).

Outputs: a table of every ROI × photo with its statistics; the ROIs with the across-view values; optionally one PNG per ROI with the views used side by side and their values.</source>
      <translation>ROI（区画）を、それが写っているすべての元画像で計測し、各 ROI についてビュー間で頑健な値を 1 つ求めます。元画像にはゴーストや継ぎ目がなく、天底に近いビューでは色が正確です。

入力は「ROI を元画像へ逆投影」と同じです：ROI ポリゴン、写真測量プロジェクト、ROI 頂点の高さ、DSM。逆投影はここで実行されます。ただし、その写真ピクセルレイヤ（「ROI を元画像へ逆投影」の OUTPUT）が指定された場合はそれをそのまま使います。

ROI と写真の組ごとに、中心が ROI のポリゴン（画枠で切り取り）内にあるピクセルから次を求めます：バンドごとの平均、中央値、標準偏差、指定したパーセンタイル（写真自身の値のまま：8 ビット、16 ビット、浮動小数点。8 ビットには変換しません）；植生指数 ExG、ExGR、VARI、GLI（赤、緑、青）と NDVI、NDRE（マルチスペクトル写真ではバンド名を指定、例 'blue,green,red,rededge,nir'）；植被率（NDVI、なければ ExG がしきい値以上のピクセルの割合：指定値、または全ビューでの大津のしきい値）；ピクセル数と GSD。DSM があれば、視線が ROI の外で地表に当たるピクセル（木、隣の株、壁に隠れる）を除外し、その割合を報告します。

ビュー間では ROI ごとに：各統計量の中央値（指定すればスコアで重み付け）、その MAD、使用したビュー（可視割合が最小値以上；最大数を設定した場合はスコアの高いもの）での最小値と最大値、ビュー数、各ビューの ROI 値からの偏差、各 ROI の最大偏差（不一致度：圃場で典型的なのは約 1、その数倍なら影、風、誤った姿勢の兆候）。斜めのビューは背の高い群落の側面を見るため、植被率と指数はビュー角とともに大きくなります：既定では最良の 3 ビューを使います。

値：保存された値のまま（写真自身の数値）、°C の温度（Zenmuse XT/XT2、Vue Pro R、Duo Pro R および FLIR ハンディ機の FLIR 放射計測 JPEG を、写真の定数と対象パラメータ（それぞれ上書き可能）でプランク曲線により変換；または係数とオフセットを指定した温度 TIFF；DJI の R-JPEG は先に DJI のツールで変換が必要）、または反射率（MicaSense と DJI のマルチスペクトルのバンドファイル、その照度センサーから）。1 回の撮影（キャプチャ）のバンドファイルは 1 つのビューです：各バンドはそれ自身のカメラで計測され、ROI × キャプチャごとに 1 行、バンドごとに 1 列となり、指数は同じ ROI のバンドの平均値と中央値から求めます。温度と反射率では列名に単位が入ります（temp_c_mean、nir_refl_median）；飽和した画素は除外されます。各ビューには写真の撮影時刻と、太陽の天頂角・方位角および位相角（太陽–区画–カメラ）も付きます。

出力：ROI × 写真ごとの統計量の表；ビュー間の値を持つ ROI；任意で ROI ごとに 1 枚の PNG（使用したビューとその値を並べて表示）。</translation>
    </message>
    <message>
      <source>Band names of the photos (comma-separated)</source>
      <translation>写真のバンド名（カンマ区切り）</translation>
    </message>
    <message>
      <source>Default: red,green,blue for 3 bands; e.g. blue,green,red,rededge,nir</source>
      <translation>既定：3 バンドなら red,green,blue。例：blue,green,red,rededge,nir</translation>
    </message>
    <message>
      <source>Values measured</source>
      <translation>計測する値</translation>
    </message>
    <message>
      <source>UTC offset of the photos' clock (hours)</source>
      <translation>写真の時計の UTC オフセット（時間）</translation>
    </message>
    <message>
      <source>For photos that do not state it (the sun's angles need UTC); empty: none</source>
      <translation>記録のない写真用（太陽の角度には UTC が必要）。空欄：なし</translation>
    </message>
    <message>
      <source>Back-projection (photo-pixel layer; empty: run it here)</source>
      <translation>逆投影（写真ピクセルのレイヤ。空欄：ここで実行）</translation>
    </message>
    <message>
      <source>Leave out pixels hidden by the DSM (when a DSM is given)</source>
      <translation>DSM に隠れるピクセルを除外（DSM 指定時）</translation>
    </message>
    <message>
      <source>Statistics of every band and index</source>
      <translation>各バンドと指数の統計量</translation>
    </message>
    <message>
      <source>Percentiles (comma-separated, 0–100; empty: none)</source>
      <translation>パーセンタイル（カンマ区切り、0–100；空：なし）</translation>
    </message>
    <message>
      <source>Vegetation indices (those the bands allow)</source>
      <translation>植生指数（バンドが許すもの）</translation>
    </message>
    <message>
      <source>Cover threshold on NDVI or ExG (empty: Otsu's)</source>
      <translation>NDVI または ExG の植被率しきい値（空：大津）</translation>
    </message>
    <message>
      <source>Minimum visible share of a ROI in a view used</source>
      <translation>使用するビューでの ROI の最小可視割合</translation>
    </message>
    <message>
      <source>Best views used per ROI (0 = all)</source>
      <translation>ROI ごとに使う最良ビュー数（0 = すべて）</translation>
    </message>
    <message>
      <source>Weight the views by their score (weighted median)</source>
      <translation>ビューをスコアで重み付け（重み付き中央値）</translation>
    </message>
    <message>
      <source>Statistics of every ROI × photo</source>
      <translation>ROI × 写真ごとの統計量</translation>
    </message>
    <message>
      <source>ROIs with their across-view statistics</source>
      <translation>ビュー間統計量付きの ROI</translation>
    </message>
    <message>
      <source>Preview per ROI (the views used, with their values)</source>
      <translation>ROI ごとのプレビュー（使用したビューとその値）</translation>
    </message>
    <message>
      <source>No DSM given: hidden pixels are not left out.</source>
      <translation>DSM が指定されていません：隠れたピクセルは除外されません。</translation>
    </message>
    <message>
      <source>Back-projection</source>
      <translation>逆投影</translation>
    </message>
    <message>
      <source>Mean</source>
      <translation>平均</translation>
    </message>
    <message>
      <source>Median</source>
      <translation>中央値</translation>
    </message>
    <message>
      <source>Standard deviation</source>
      <translation>標準偏差</translation>
    </message>
    <message>
      <source>{rois}: plot statistics from the photos of {project}</source>
      <translation>{rois}：{project} の写真からの区画統計</translation>
    </message>
    <message>
      <source>{rois}: statistics per photo</source>
      <translation>{rois}：写真ごとの統計量</translation>
    </message>
    <message>
      <source>Back-projection from the layer '{name}': {k} ROI × photo pairs.</source>
      <translation>レイヤ「{name}」からの逆投影：{k} 組の ROI × 写真。</translation>
    </message>
    <message>
      <source>{n} ROI(s) without a view used: {names}</source>
      <translation>使用できるビューのない ROI が {n} 個：{names}</translation>
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
      <translation>各 ROI（区画、樹木、植物のポリゴン）について、その内側にある点群（.las、.laz または .ply）の点と、その地面からの高さを求めます：樹冠高、そのパーセンタイル、点密度など。例えば草丈やバイオマスのモデルに使用できます。

結果は ROI レイヤの属性に次を加えたものです：count（内側の点数）、density（点群の CRS の単位面積あたりの点数。メートル単位の点群では m² あたり）、z_min、z_mean、z_max（点の Z）、ground（点の下の地面の Z の平均）、h_mean、h_max、および指定した各高さパーセンタイルの h_pNN（地面からの高さ：Z − ground）（既定は 5、50、95、99。p99 はロバストな樹冠頂部です）。

地面：各点の下でサンプリングする DSM/DTM ラスタ（出芽前に飛行した裸地の DSM、または数値地形モデル（DTM））、一定の地面の高さ、またはどちらもない場合は各 ROI 自身の最も低い点、つまりその Z の指定パーセンタイル（高度な設定、既定は 1）。ラスタと高さは、点群の Z の単位と高さ基準で指定する必要があります。

LAS/LAZ ファイルは CRS を持ちますが、PLY ファイルは持たないため、「点群の座標参照系」を指定してください（CRS のない LAS ファイルでも同様です）。別の CRS の ROI は再投影されます。点を含まない ROI はログに名前が示されます。その count と density は 0、Z と高さは空（NULL）となり、0 にはなりません。</translation>
    </message>
    <message>
      <source>ROIs (polygons)</source>
      <translation>ROI（ポリゴン）</translation>
    </message>
    <message>
      <source>Ground: DSM or DTM raster (GeoTIFF)</source>
      <translation>地面：DSM または DTM のラスタ（GeoTIFF）</translation>
    </message>
    <message>
      <source>Ground otherwise: percentile of each ROI's Z</source>
      <translation>それ以外の地面：各 ROI の Z のパーセンタイル</translation>
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
      <translation>地面：DSM/DTM ラスタか地面の高さのどちらか一方を指定してください。両方は指定できません。</translation>
    </message>
    <message>
      <source>Ground DSM/DTM</source>
      <translation>地面 DSM/DTM</translation>
    </message>
    <message>
      <source>The ROI layer's own fields with the names of the statistics are replaced by the new values.</source>
      <translation>ROI レイヤ自体にある、統計量と同じ名前のフィールドは新しい値で置き換えられます。</translation>
    </message>
    <message>
      <source>Ground: one height for all ROIs (cloud Z units)</source>
      <translation>地面：全 ROI に共通の高さ（点群の Z の単位）</translation>
    </message>
    <message>
      <source>{rois}: point cloud heights of {cloud}</source>
      <translation>{rois}：{cloud} の点群の高さ</translation>
    </message>
    <message>
      <source>Statistics of {n_rois} ROIs written, {n} with points{shown}.</source>
      <translation>{n_rois} 個の ROI の統計量を書き出しました。点を含むもの：{n} 個{shown}。</translation>
    </message>
    <message>
      <source>Ground: the raster {name} under every point.</source>
      <translation>地面：各点の下のラスタ {name}。</translation>
    </message>
    <message>
      <source>Ground: percentile {ground_pct:g} of each ROI's Z.</source>
      <translation>地面：各 ROI の Z の {ground_pct:g} パーセンタイル。</translation>
    </message>
    <message>
      <source>None of the {n_rois} ROIs contains a point of the cloud: check that the ROIs and the cloud are in the right CRS (set 'Point cloud CRS' if the file has none or a wrong one) and the Z range.</source>
      <translation>{n_rois} 個の ROI のいずれにも点群の点が含まれていません。ROI と点群の CRS が正しいか（ファイルに CRS がないか誤っている場合は「点群の座標参照系」を設定してください）、および Z 範囲を確認してください。</translation>
    </message>
    <message>
      <source>The ground raster {name} has no data under the points of {n} of the {total} ROIs (outside it or nodata): their heights above ground are empty. Check that it covers the ROIs.</source>
      <translation>地面のラスタ {name} には、{total} 個中 {n} 個の ROI で点の下にデータがありません（範囲外または NoData 値）。これらの地面からの高さは空になります。ラスタが ROI を覆っているか確認してください。</translation>
    </message>
    <message>
      <source>{n} ROI(s) contain no point (outside the cloud, in a gap, or outside the Z range); their statistics are empty: feature id {ids}.</source>
      <translation>{n} 個の ROI に点が含まれていません（点群の範囲外、欠損部、または Z 範囲外）。これらの統計量は空です：地物 ID {ids}。</translation>
    </message>
    <message>
      <source>Ground: {height:g} for every ROI.</source>
      <translation>地面：すべての ROI で {height:g}。</translation>
    </message>
    <message>
      <source> (map colours: {field})</source>
      <translation>（地図の色分け：{field}）</translation>
    </message>
    <message>
      <source>ROI heights from DSM</source>
      <translation>DSM から ROI の高さを取得</translation>
    </message>
    <message>
      <source>Gives every ROI its height from a surface model (DSM), as the Z of its vertices and as the attribute 'height' (in the DSM's units and vertical reference). The result is the ROI layer as PolygonZ, ready for backward projection into raw photos.

Per polygon: the statistic (mean, median, min, max, a percentile, e.g. 90 for canopy top, 5 for ground, the standard deviation, or EasyIDP's pmin/pmax: the mean of the values below the percentile / above 100 minus the percentile) of the DSM pixels whose centres are inside the ROI, grown by a positive buffer or shrunk by a negative one (map units of the DSM). Every vertex gets that height.
Per vertex: the DSM height at each vertex (bilinear or nearest pixel), or, with a buffer, the statistic of the pixels within the buffer distance of the vertex; 'height' is then the mean of the vertex heights.

Nodata pixels are ignored. An ROI without any valid pixel keeps an empty (NULL) height and NaN Z, and is listed in the log; it never gets 0.</source>
      <translation>各 ROI に数値表層モデル（DSM）からの高さを、頂点の Z と属性 'height' として付与します（DSM の単位と高さ基準）。結果は PolygonZ の ROI レイヤとなり、元画像（撮影写真）への逆投影にそのまま使用できます。

ポリゴンごと：ROI 内に中心がある DSM ピクセルの統計量（平均、中央値、最小、最大、パーセンタイル（例：樹冠頂部には 90、地面には 5）、標準偏差、または EasyIDP の pmin/pmax：パーセンタイル未満の値の平均 / 100 からパーセンタイルを引いた値を超える値の平均）。ROI は正のバッファ距離で拡大、負のバッファ距離で縮小されます（DSM の地図単位）。すべての頂点にその高さが設定されます。
頂点ごと：各頂点での DSM の高さ（バイリニアまたは最近傍ピクセル）、またはバッファ距離を指定した場合は頂点からバッファ距離内のピクセルの統計量。その場合 'height' は頂点の高さの平均になります。

NoData 値のピクセルは無視されます。有効なピクセルが 1 つもない ROI は高さが空（NULL）、Z が NaN のままとなり、ログに示されます。0 になることはありません。</translation>
    </message>
    <message>
      <source>Per polygon: one statistic of the DSM pixels inside</source>
      <translation>ポリゴンごと：ROI 内の DSM ピクセルの統計量を 1 つ</translation>
    </message>
    <message>
      <source>Per vertex: the DSM height at each vertex</source>
      <translation>頂点ごと：各頂点での DSM の高さ</translation>
    </message>
    <message>
      <source>Vertex sampling</source>
      <translation>頂点のサンプリング</translation>
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
      <source>Buffer (DSM map units; negative shrinks the polygon)</source>
      <translation>バッファ（DSM の地図単位、負の値でポリゴンを縮小）</translation>
    </message>
    <message>
      <source>ROIs with heights</source>
      <translation>高さ付き ROI</translation>
    </message>
    <message>
      <source>Percentile (0–100; for percentile, pmin and pmax)</source>
      <translation>パーセンタイル（0–100。percentile、pmin、pmax 用）</translation>
    </message>
    <message>
      <source>{rois}: height {what} from {dsm}</source>
      <translation>{rois}：{dsm} からの高さ {what}</translation>
    </message>
    <message>
      <source>ROI '{name}': {reason}; its height is left empty.</source>
      <translation>ROI '{name}'：{reason}。高さは空のままです。</translation>
    </message>
    <message>
      <source>Heights ({what}) of {n} ROIs: {lo:.3f} to {hi:.3f} (DSM units), {null} empty (NULL).</source>
      <translation>{n} 個の ROI の高さ（{what}）：{lo:.3f}～{hi:.3f}（DSM の単位）、空（NULL）{null} 個。</translation>
    </message>
    <message>
      <source>Heights of {n} ROIs: all empty (NULL): {reason}.</source>
      <translation>{n} 個の ROI の高さはすべて空（NULL）です：{reason}。</translation>
    </message>
    <message>
      <source>Heights of {n} ROIs: all empty (NULL): the DSM has no valid pixel under any of them.</source>
      <translation>{n} 個の ROI の高さ：すべて空（NULL）です。どの ROI の下にも DSM の有効なピクセルがありません。</translation>
    </message>
    <message>
      <source>see the warnings above for each ROI</source>
      <translation>各 ROI の理由は上の警告を参照してください</translation>
    </message>
    <message>
      <source>Plot traits over a season</source>
      <translation>シーズンを通した区画の形質</translation>
    </message>
    <message>
      <source>Time series</source>
      <translation>時系列</translation>
    </message>
    <message>
      <source>Traits of every ROI (plot, tree) on every date of a season of surveys: plant height from the DSMs, canopy cover, band means and a vegetation index from the orthomosaics, heights from the point clouds. Each file is read once for all ROIs; the files are shared out to worker processes on this computer, or to a Dask cluster.

Survey table: a CSV file or a table layer with the columns date (YYYY-MM-DD), orthomosaic, dsm, point_cloud and project (file paths, absolute or relative to the table's folder; empty cells allowed); optional: bands (the orthomosaic's band names in order, e.g. blue,green,red,rededge,nir: NDVI needs red and nir) and crs (for files without one, e.g. PLY). Rows with a missing file, an unreadable raster or a CRS that cannot be related to the ROIs are reported by row and left out; the rest completes. The project column is read but not used by the traits yet.

Traits: height_pNN (percentiles of the DSM above the ground, metres); cover (share of the ROI whose vegetation index is above the threshold, 0-1; Otsu's automatic threshold per orthomosaic, or a given one); exg (excess green, RGB) or ndvi (named bands); mean_&lt;band&gt; (band means); cloud_points and cloud_height_pNN (point clouds).

Ground: a bare-soil DSM or DTM of the season (a flight before emergence): a plane is fitted to it under each ROI. Without one, each ROI's ground is the plane through the lowest heights (the given percentile) in a 3 × 3 grid over it, which needs bare soil between the plants.

Workers: processes on this computer. Dask scheduler (advanced): tcp://host:8786 to run on a Dask cluster (the files must be at the same paths on every worker), or 'local' for a Dask cluster of 'Workers' processes on this computer.

Outputs: the long table (roi, date, trait, value); the ROIs with the traits of their latest date (styled by height); growth curves as a PNG (a panel per ROI, or per group when there are many ROIs and a group field); optionally the crops, in &lt;date&gt;/&lt;orthomosaic|dsm|point_cloud&gt;/ folders.</source>
      <translation>シーズン中の一連の空撮の各日付について、各 ROI（区画、樹木）の形質を求めます：DSM からの草丈、オルソモザイクからの植被率、バンド平均値、植生指数、点群からの高さ。各ファイルはすべての ROI に対して 1 回だけ読み込まれます。ファイルはこのコンピュータ上のワーカープロセス、または Dask クラスタに分配されます。

空撮一覧表：date（YYYY-MM-DD）、orthomosaic、dsm、point_cloud、project の列を持つ CSV ファイルまたはテーブルレイヤです（ファイルパスは絶対パス、または表のフォルダからの相対パス。空のセルも可）。オプション：bands（オルソモザイクのバンド名を順番に。例：blue,green,red,rededge,nir。NDVI には red と nir が必要）と crs（CRS のないファイル用。例：PLY）。ファイルが見つからない行、ラスタが読めない行、ROI と関連付けられない CRS の行は、行ごとに報告されて除外され、残りは最後まで処理されます。project 列は読み込まれますが、現時点では形質にはまだ使用されません。

形質：height_pNN（地面からの DSM の高さのパーセンタイル、メートル）、cover（植生指数がしきい値を超える ROI の割合、0-1。オルソモザイクごとの大津の自動しきい値、または指定値）、exg（過剰緑色指数、RGB）または ndvi（名前付きバンド）、mean_&lt;band&gt;（バンド平均値）、cloud_points と cloud_height_pNN（点群）。

地面：シーズンの裸地の DSM または数値地形モデル（DTM）（出芽前の飛行）。各 ROI の下でこれに平面を当てはめます。ない場合、各 ROI の地面は、ROI 上の 3 × 3 グリッドにおける最も低い高さ（指定パーセンタイル）を通る平面となるため、植物の間に裸地が見えている必要があります。

ワーカープロセス：このコンピュータ上のプロセス数。Dask スケジューラ（高度な設定）：Dask クラスタで実行するには tcp://host:8786（ファイルはすべてのワーカーで同じパスにある必要があります）、このコンピュータ上で「ワーカープロセス」の数のプロセスによる Dask クラスタを使うには 'local'。

出力：縦長の表（roi、date、trait、value）、最新の日付の形質を持つ ROI（高さで色分け）、PNG の生育曲線（ROI ごと、または ROI が多くグループフィールドがある場合はグループごとに 1 パネル）、オプションで &lt;date&gt;/&lt;orthomosaic|dsm|point_cloud&gt;/ フォルダ内の切り出し。</translation>
    </message>
    <message>
      <source>Dask scheduler (tcp://host:port or 'local')</source>
      <translation>Dask スケジューラ（tcp://host:port または 'local'）</translation>
    </message>
    <message>
      <source>Empty: processes on this computer</source>
      <translation>空欄：このコンピュータ上のプロセス</translation>
    </message>
    <message>
      <source>Survey table (CSV file or table layer)</source>
      <translation>空撮一覧表（CSV ファイルまたはテーブルレイヤ）</translation>
    </message>
    <message>
      <source>Name field (unique; default: feature id)</source>
      <translation>名前フィールド（一意。既定：地物 ID）</translation>
    </message>
    <message>
      <source>Group field (treatment, variety: colours the curves)</source>
      <translation>グループフィールド（処理区、品種：曲線を色分け）</translation>
    </message>
    <message>
      <source>Traits</source>
      <translation>形質</translation>
    </message>
    <message>
      <source>Ground: bare-soil DSM or DTM of the season</source>
      <translation>地面：シーズンの裸地 DSM または DTM</translation>
    </message>
    <message>
      <source>Ground without a DTM: percentile of the lowest heights</source>
      <translation>DTM がないときの地面：最も低い高さのパーセンタイル</translation>
    </message>
    <message>
      <source>Cover threshold on the vegetation index (empty: Otsu)</source>
      <translation>植生指数の被覆しきい値（空欄：大津の方法）</translation>
    </message>
    <message>
      <source>Worker processes</source>
      <translation>ワーカープロセス</translation>
    </message>
    <message>
      <source>Crops per date (folder)</source>
      <translation>日付ごとの切り出し（フォルダ）</translation>
    </message>
    <message>
      <source>Traits per ROI and date (long table)</source>
      <translation>ROI と日付ごとの形質（縦長の表）</translation>
    </message>
    <message>
      <source>ROIs with their latest traits</source>
      <translation>最新の形質付き ROI</translation>
    </message>
    <message>
      <source>Growth curves (PNG)</source>
      <translation>生育曲線（PNG）</translation>
    </message>
    <message>
      <source>PNG files (*.png)</source>
      <translation>PNG ファイル (*.png)</translation>
    </message>
    <message>
      <source>Survey table: no table given, or it could not be loaded.</source>
      <translation>空撮一覧表：表が指定されていないか、読み込めませんでした。</translation>
    </message>
    <message>
      <source>Traits: choose at least one.</source>
      <translation>形質：少なくとも 1 つ選択してください。</translation>
    </message>
    <message>
      <source>Ground</source>
      <translation>地面</translation>
    </message>
    <message>
      <source>No trait could be computed: every survey row was left out (see the messages above).</source>
      <translation>形質を 1 つも計算できませんでした：空撮一覧表のすべての行が除外されました（上記のメッセージを参照してください）。</translation>
    </message>
    <message>
      <source>{n} surveys, {r} ROIs, traits: {t}</source>
      <translation>空撮 {n} 件、ROI {r} 個、形質：{t}</translation>
    </message>
    <message>
      <source>{v} values of {k} traits for {r} ROIs on {d} dates in {s:.0f} s ({e}); {p} rows or files left out.</source>
      <translation>{d} 日分の {r} 個の ROI について、{k} 種類の形質の値 {v} 件を {s:.0f} s で計算しました（{e}）。除外した行またはファイル：{p} 件。</translation>
    </message>
    <message>
      <source>{rois}: latest traits</source>
      <translation>{rois}：最新の形質</translation>
    </message>
    <message>
      <source>{rois}: traits per date</source>
      <translation>{rois}：日付ごとの形質</translation>
    </message>
    <message>
      <source>Height from the DSM</source>
      <translation>DSM からの高さ</translation>
    </message>
    <message>
      <source>Canopy cover</source>
      <translation>植被率</translation>
    </message>
    <message>
      <source>Band means</source>
      <translation>バンド平均値</translation>
    </message>
    <message>
      <source>Vegetation index (ExG or NDVI)</source>
      <translation>植生指数（ExG または NDVI）</translation>
    </message>
    <message>
      <source>Heights from the point cloud</source>
      <translation>点群からの高さ</translation>
    </message>
    <message>
      <source>Survey {p}</source>
      <translation>空撮 {p}</translation>
    </message>
    <message>
      <source>Left out: {p}</source>
      <translation>除外：{p}</translation>
    </message>
    <message>
      <source>QGIS's own {packages}: the plugin does not replace QGIS's packages; use a newer QGIS.</source>
      <translation>QGIS 本体の {packages}：このプラグインは QGIS のパッケージを置き換えません。より新しい QGIS を使用してください。</translation>
    </message>
    <message>
      <source>{tool} needs Python packages that QGIS's Python does not have: {packages}.</source>
      <translation>{tool} には、QGIS の Python にない Python パッケージが必要です：{packages}。</translation>
    </message>
    <message>
      <source>Nothing was installed.</source>
      <translation>何もインストールされませんでした。</translation>
    </message>
    <message>
      <source>The plugin's Python packages are installed with the Install button the QGIS desktop shows when one is missing, or by running:
{command}</source>
      <translation>プラグインの Python パッケージは、不足しているときに QGIS デスクトップに表示される［インストール］ボタンでインストールするか、次のコマンドを実行してインストールします：
{command}</translation>
    </message>
    <message>
      <source>{name} {version} (needs {spec})</source>
      <translation>{name} {version}（{spec} が必要）</translation>
    </message>
    <message>
      <source>{python} is Python {got}, but QGIS runs Python {want}; QGIS's own interpreter was not found</source>
      <translation>{python} は Python {got} ですが、QGIS は Python {want} で動作しています。QGIS 自身のインタプリタが見つかりませんでした</translation>
    </message>
    <message>
      <source>{error}. Install the missing Python package for QGIS's Python ({python}).</source>
      <translation>{error}。QGIS の Python（{python}）に、不足している Python パッケージをインストールしてください。</translation>
    </message>
    <message>
      <source>QGIS's Python interpreter {python} cannot run: {error}</source>
      <translation>QGIS の Python インタプリタ {python} を実行できません：{error}</translation>
    </message>
    <message>
      <source>To install them, click Install in the EasyIDP message bar of the QGIS desktop, or run:
{command}</source>
      <translation>インストールするには、QGIS デスクトップの EasyIDP メッセージバーで［インストール］をクリックするか、次のコマンドを実行してください：
{command}</translation>
    </message>
    <message>
      <source>Installing Python packages for EasyIDP</source>
      <translation>EasyIDP 用の Python パッケージをインストールしています</translation>
    </message>
    <message>
      <source>Cancel</source>
      <translation>キャンセル</translation>
    </message>
    <message>
      <source>Some tools need Python packages that QGIS's Python lacks: {packages}.</source>
      <translation>一部のツールには、QGIS の Python にない Python パッケージが必要です：{packages}。</translation>
    </message>
    <message>
      <source>Install</source>
      <translation>インストール</translation>
    </message>
    <message>
      <source>Download them with pip into your QGIS profile; QGIS's own packages are not changed.</source>
      <translation>pip で QGIS のプロファイルにダウンロードします。QGIS 本体のパッケージは変更されません。</translation>
    </message>
    <message>
      <source>Every Python package EasyIDP needs is installed.</source>
      <translation>EasyIDP に必要な Python パッケージはすべてインストールされています。</translation>
    </message>
    <message>
      <source>Installing {packages} …</source>
      <translation>{packages} をインストールしています…</translation>
    </message>
    <message>
      <source>Python packages installed: {packages}.</source>
      <translation>Python パッケージをインストールしました：{packages}。</translation>
    </message>
    <message>
      <source>Restart QGIS to use them: an older copy is already loaded.</source>
      <translation>使用するには QGIS を再起動してください：古いバージョンが既に読み込まれています。</translation>
    </message>
    <message>
      <source>nothing was missing</source>
      <translation>不足しているものはありませんでした</translation>
    </message>
    <message>
      <source>Installation cancelled; nothing was changed. To install later, run:
{command}</source>
      <translation>インストールをキャンセルしました。何も変更されていません。後でインストールするには、次のコマンドを実行してください：
{command}</translation>
    </message>
    <message>
      <source>Installing the Python packages failed: {reason}. Run this command in a terminal to see why:
{command}</source>
      <translation>Python パッケージのインストールに失敗しました：{reason}。原因を確認するには、ターミナルで次のコマンドを実行してください：
{command}</translation>
    </message>
    <message>
      <source>still missing after pip: {packages}</source>
      <translation>pip の実行後も不足しています：{packages}</translation>
    </message>
    <message>
      <source>exit status {code}</source>
      <translation>終了ステータス {code}</translation>
    </message>
    <message>
      <source>you may not read it (permissions)</source>
      <translation>読み取り権限がありません</translation>
    </message>
    <message>
      <source>it is empty (0 bytes)</source>
      <translation>ファイルが空です（0 バイト）</translation>
    </message>
    <message>
      <source>it is JSON but not GeoJSON (no FeatureCollection)</source>
      <translation>JSON ですが GeoJSON ではありません（FeatureCollection がありません）</translation>
    </message>
    <message>
      <source>it is not UTF-8 text, so not GeoJSON</source>
      <translation>UTF-8 テキストではないため GeoJSON ではありません</translation>
    </message>
    <message>
      <source>it is not a TIFF file (it starts with {head!r})</source>
      <translation>TIFF ファイルではありません（先頭は {head!r}）</translation>
    </message>
    <message>
      <source>GDAL cannot open it ({error})</source>
      <translation>GDAL で開けません（{error}）</translation>
    </message>
    <message>
      <source>not a format it knows</source>
      <translation>既知の形式ではありません</translation>
    </message>
    <message>
      <source>{name}: {path} exists but cannot be read as a layer: {why}. Check the file, or save it again from the program that made it.</source>
      <translation>{name}：{path} は存在しますが、レイヤとして読み込めません：{why}。ファイルを確認するか、作成したプログラムで保存し直してください。</translation>
    </message>
    <message>
      <source>it is not valid JSON ({error}); it may be cut short</source>
      <translation>有効な JSON ではありません（{error}）。ファイルが途中で切れている可能性があります</translation>
    </message>
    <message>
      <source>ROI file not found: {path}</source>
      <translation>ROI ファイルが見つかりません：{path}</translation>
    </message>
    <message>
      <source>{path}: file not found.</source>
      <translation>{path}：ファイルが見つかりません。</translation>
    </message>
    <message>
      <source>The ROIs have no CRS: set one on the layer before using it.</source>
      <translation>ROI に座標参照系がありません。使用する前にレイヤに座標参照系を設定してください。</translation>
    </message>
    <message>
      <source>The ROI layer has no features.</source>
      <translation>ROI レイヤに地物がありません。</translation>
    </message>
    <message>
      <source>None of the {count} ROIs overlaps the raster {raster}. Raster extent {raster_extent}, ROI extent {roi_extent} (both in {crs}). Check that the ROI layer and the raster cover the same area and that the ROI layer's CRS is set correctly.</source>
      <translation>{count} 個の ROI のどれもラスタ {raster} と重なりません。ラスタの範囲 {raster_extent}、ROI の範囲 {roi_extent}（どちらも {crs}）。ROI レイヤとラスタが同じ地域を覆っているか、ROI レイヤの座標参照系が正しく設定されているかを確認してください。</translation>
    </message>
    <message>
      <source>No ROI is seen by any photo: check that the ROIs lie in the surveyed area and in the right CRS.</source>
      <translation>どの写真にも ROI が写っていません。ROI が測量範囲内にあり、座標参照系が正しいかを確認してください。</translation>
    </message>
    <message>
      <source>Nothing to write: give a crops folder, a previews folder or both.</source>
      <translation>書き出すものがありません。切り出しフォルダ、プレビューフォルダ、またはその両方を指定してください。</translation>
    </message>
    <message>
      <source>GDAL cannot open it as a GeoPackage; {size:.0f} KiB</source>
      <translation>GDAL で GeoPackage として開けません。{size:.0f} KiB</translation>
    </message>
    <message>
      <source>it is on a read-only file system</source>
      <translation>読み取り専用のファイルシステム上にあります</translation>
    </message>
    <message>
      <source>{output}: {folder} is a file, not a folder. Choose another file.</source>
      <translation>{output}：{folder} はフォルダではなくファイルです。別のファイルを選んでください。</translation>
    </message>
    <message>
      <source>{output}: the folder {folder} does not exist and cannot be created. Create it, or choose another file.</source>
      <translation>{output}：フォルダ {folder} が存在せず、作成もできません。作成するか、別のファイルを選んでください。</translation>
    </message>
    <message>
      <source>'{a}' and '{b}' are both {path}: one would replace the other. Choose two files.</source>
      <translation>'{a}' と '{b}' がどちらも {path} です。一方が他方を置き換えてしまいます。別々のファイルを選択してください。</translation>
    </message>
    <message>
      <source>you may not write there ({reason})</source>
      <translation>書き込み権限がありません（{reason}）</translation>
    </message>
    <message>
      <source>{output}: {path} cannot be written: {why}. Choose a folder you can write to.</source>
      <translation>{output}：{path} に書き込めません：{why}。書き込めるフォルダを選んでください。</translation>
    </message>
    <message>
      <source>{output}: {path} is also the input '{input}'. Inputs are never overwritten: choose another file.</source>
      <translation>{output}：{path} は入力 '{input}' でもあります。入力は上書きされません。別のファイルを選択してください。</translation>
    </message>
    <message>
      <source>{name}: {value} is not a number; give a finite value.</source>
      <translation>{name}：{value} は数値ではありません。有限の値を指定してください。</translation>
    </message>
    <message>
      <source>{name}: {value:g} is outside the range {lo}–{hi}.</source>
      <translation>{name}：{value:g} は範囲 {lo}–{hi} の外です。</translation>
    </message>
    <message>
      <source>{output}: another run ({holder}) is writing {path}; nothing was written. Wait for it to finish, or choose another file.</source>
      <translation>{output}：別の実行（{holder}）が {path} に書き込み中です。何も書き込んでいません。終わるまで待つか、別のファイルを選んでください。</translation>
    </message>
    <message>
      <source>{output}: {path} was not a valid GeoPackage ({why}), the leftover of an interrupted run; it is replaced.</source>
      <translation>{output}：{path} は有効な GeoPackage ではありません（{why}）。中断された実行の残りです。置き換えます。</translation>
    </message>
    <message>
      <source>{output}: {path} already exists and nothing was written. Choose another file, or tick 'Overwrite existing files' (advanced) to replace it.</source>
      <translation>{output}：{path} は既に存在するため、何も書き出しませんでした。別のファイルを選択するか、「既存のファイルを上書き」（高度な設定）をオンにして置き換えてください。</translation>
    </message>
    <message>
      <source>{name}: {value} is not one of the choices ({opts}).</source>
      <translation>{name}：{value} は選択肢（{opts}）のいずれでもありません。</translation>
    </message>
    <message>
      <source>Lowest Z to keep (cloud Z units; empty: no limit)</source>
      <translation>残す最低 Z（点群の Z 単位、空欄：制限なし）</translation>
    </message>
    <message>
      <source>Highest Z to keep (cloud Z units; empty: no limit)</source>
      <translation>残す最高 Z（点群の Z 単位、空欄：制限なし）</translation>
    </message>
    <message>
      <source>Percentiles: '{token}' is not a number from 0 to 100. Give percentiles separated by commas, e.g. 5,50,95.</source>
      <translation>パーセンタイル：「{token}」は 0 から 100 の数ではありません。カンマ区切りで指定してください（例 5,50,95）。</translation>
    </message>
    <message>
      <source>EasyIDP photo viewer</source>
      <translation>EasyIDP 写真ビューア</translation>
    </message>
    <message>
      <source>Photogrammetry projects (*.psx *.psz *.xml *.p4d *.opf *.json);;All files (*)</source>
      <translation>写真測量プロジェクト (*.psx *.psz *.xml *.p4d *.opf *.json);;すべてのファイル (*)</translation>
    </message>
    <message>
      <source>Project</source>
      <translation>プロジェクト</translation>
    </message>
    <message>
      <source>Used when no DSM is chosen: one ground height, in the project's vertical reference</source>
      <translation>DSM を選ばないときに使用：プロジェクトの高さ基準での地面の高さ 1 つ</translation>
    </message>
    <message>
      <source>Ground height without a DSM</source>
      <translation>DSM なしの地面の高さ</translation>
    </message>
    <message>
      <source>Layer in photo pixels</source>
      <translation>写真ピクセルのレイヤ</translation>
    </message>
    <message>
      <source>Click a point</source>
      <translation>点をクリック</translation>
    </message>
    <message>
      <source>Selected plots</source>
      <translation>選択した区画</translation>
    </message>
    <message>
      <source>Show layer</source>
      <translation>レイヤを表示</translation>
    </message>
    <message>
      <source>EasyIDP viewer: decoding photos</source>
      <translation>EasyIDP ビューア：写真をデコード中</translation>
    </message>
    <message>
      <source>Images (*.png *.jpg *.tif)</source>
      <translation>画像 (*.png *.jpg *.tif)</translation>
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
      <translation>写真</translation>
    </message>
    <message>
      <source>ROI</source>
      <translation>ROI</translation>
    </message>
    <message>
      <source>Rank</source>
      <translation>順位</translation>
    </message>
    <message>
      <source>Score</source>
      <translation>スコア</translation>
    </message>
    <message>
      <source>View angle (°)</source>
      <translation>視角 (°)</translation>
    </message>
    <message>
      <source>GSD</source>
      <translation>GSD</translation>
    </message>
    <message>
      <source>Visible</source>
      <translation>可視</translation>
    </message>
    <message>
      <source>Occluded</source>
      <translation>遮蔽</translation>
    </message>
    <message>
      <source>Save the shown crop…</source>
      <translation>表示中の切り抜きを保存…</translation>
    </message>
    <message>
      <source>Save the outline as LabelMe…</source>
      <translation>輪郭を LabelMe で保存…</translation>
    </message>
    <message>
      <source>Choose the photogrammetry project first.</source>
      <translation>先に写真測量プロジェクトを選んでください。</translation>
    </message>
    <message>
      <source>No layer in photo pixels: run Back-project ROIs first.</source>
      <translation>写真ピクセルのレイヤがありません：先に「ROI を元画像へ逆投影」を実行してください。</translation>
    </message>
    <message>
      <source>A clicked point has no outline: select plots.</source>
      <translation>クリックした点には輪郭がありません：区画を選んでください。</translation>
    </message>
    <message>
      <source>Select plots in a polygon layer first.</source>
      <translation>先にポリゴンレイヤで区画を選んでください。</translation>
    </message>
    <message>
      <source>{n} ROI × photo pairs of {layer}.</source>
      <translation>{layer} の ROI × 写真の組 {n} 件。</translation>
    </message>
    <message>
      <source>{photo}: {roi}, rank {rank}, score {score:.2f}</source>
      <translation>{photo}：{roi}、順位 {rank}、スコア {score:.2f}</translation>
    </message>
    <message>
      <source>{n} photos see it.</source>
      <translation>{n} 枚の写真に写っています。</translation>
    </message>
    <message>
      <source>No photo sees it: {why}</source>
      <translation>写っている写真はありません：{why}</translation>
    </message>
    <message>
      <source>Could not write {path}.</source>
      <translation>{path} を書き込めませんでした。</translation>
    </message>
    <message>
      <source>Written: {path}</source>
      <translation>書き込みました：{path}</translation>
    </message>
    <message>
      <source>Emissivity (empty: the photo's)</source>
      <translation>放射率（空欄：写真の値）</translation>
    </message>
    <message>
      <source>Object distance, m (empty: the photo's)</source>
      <translation>対象までの距離、m（空欄：写真の値）</translation>
    </message>
    <message>
      <source>Reflected apparent temperature, °C (empty: the photo's)</source>
      <translation>反射見かけ温度、°C（空欄：写真の値）</translation>
    </message>
    <message>
      <source>Atmospheric temperature, °C (empty: the photo's)</source>
      <translation>気温、°C（空欄：写真の値）</translation>
    </message>
    <message>
      <source>Relative humidity, % (empty: the photo's)</source>
      <translation>相対湿度、%（空欄：写真の値）</translation>
    </message>
    <message>
      <source>IR window temperature, °C (empty: the photo's)</source>
      <translation>赤外線窓の温度、°C（空欄：写真の値）</translation>
    </message>
    <message>
      <source>IR window transmission, 0–1 (empty: the photo's)</source>
      <translation>赤外線窓の透過率、0–1（空欄：写真の値）</translation>
    </message>
    <message>
      <source>Temperature TIFFs store</source>
      <translation>温度 TIFF の保存形式</translation>
    </message>
    <message>
      <source>°C</source>
      <translation>°C</translation>
    </message>
    <message>
      <source>Kelvin</source>
      <translation>ケルビン</translation>
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
      <translation>センチケルビン（K × 100）</translation>
    </message>
    <message>
      <source>Temperature TIFF scale (°C = stored × scale + offset)</source>
      <translation>温度 TIFF の係数（°C = 保存値 × 係数 + オフセット）</translation>
    </message>
    <message>
      <source>Empty: the preset's</source>
      <translation>空欄：プリセットの値</translation>
    </message>
    <message>
      <source>Temperature TIFF offset, °C (empty: the preset)</source>
      <translation>温度 TIFF のオフセット、°C（空欄：プリセット）</translation>
    </message>
    <message>
      <source>As stored</source>
      <translation>保存された値のまま</translation>
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
      <translation>写真ビューア：どの写真に写っている？</translation>
    </message>
    <message>
      <source>Point cloud (.las, .laz or .ply)</source>
      <translation>点群（.las、.laz または .ply）</translation>
    </message>
    <message>
      <source>Needed for PLY, and for LAS/LAZ without a CRS; otherwise read from the file (a CRS given here replaces the file's)</source>
      <translation>PLY と、座標参照系のない LAS/LAZ で必要。それ以外はファイルから読みます（ここで指定するとファイルのものを置き換えます）</translation>
    </message>
    <message>
      <source>Point cloud CRS</source>
      <translation>点群の座標参照系</translation>
    </message>
    <message>
      <source>Off: only the index opens (when it is set to open). On: the files too, in one collapsed group below the ROI layer; none when there are more than {n} (the log says where they are).</source>
      <translation>オフ：索引だけを開きます（開く設定の場合）。オン：ファイルも ROI レイヤの下の折りたたんだグループに開きます。{n} 個を超えるときは開きません（ログに場所を示します）。</translation>
    </message>
    <message>
      <source>Other photos of the ROI</source>
      <translation>ROI のその他の写真</translation>
    </message>
    <message>
      <source>The ROI's best photo (rank 1)</source>
      <translation>ROI の最良の写真（順位 1）</translation>
    </message>
    <message>
      <source>No file (skipped: see its status)</source>
      <translation>ファイルなし（スキップ：状態を参照）</translation>
    </message>
    <message>
      <source>File written</source>
      <translation>ファイルを書き出し済み</translation>
    </message>
    <message>
      <source>{n} files are more than the {limit} loaded into the map: open them from the output folder.</source>
      <translation>{n} 個のファイルは、地図に読み込む上限の {limit} 個を超えています。出力フォルダから開いてください。</translation>
    </message>
    <message>
      <source>In photo pixels, not loaded into the map: {path}</source>
      <translation>写真ピクセルのため地図には読み込みません：{path}</translation>
    </message>
    <message>
      <source>For Pix4D without a *_wkt.prj file, OpenSfM without OpenDroneMap, or a Metashape chunk CRS that PROJ cannot use; for a folder of photos, default: their UTM zone</source>
      <translation>*_wkt.prj ファイルのない Pix4D、OpenDroneMap のない OpenSfM、または PROJ が扱えない Metashape チャンクの座標参照系の場合。写真フォルダでは既定で写真の UTM ゾーン</translation>
    </message>
    <message>
      <source>Camera heights (a folder of photos)</source>
      <translation>カメラの高さ（写真フォルダ）</translation>
    </message>
    <message>
      <source>Take-off height (m; a folder of photos)</source>
      <translation>離陸地点の高さ（m。写真フォルダ）</translation>
    </message>
    <message>
      <source>In the DSM's vertical reference: added to the photos' relative altitude</source>
      <translation>DSM の高さ基準で指定：写真の相対高度に加えます</translation>
    </message>
    <message>
      <source>Metashape .psx/.psz/.xml; Pix4D .p4d, project or params folder; OpenDroneMap folder or reconstruction.json; OPF project.opf; or a folder of drone photos (cameras from their EXIF/XMP tags: rough, see the log's uncertainty)</source>
      <translation>Metashape の .psx/.psz/.xml、Pix4D の .p4d・プロジェクトフォルダ・params フォルダ、OpenDroneMap のフォルダまたは reconstruction.json、OPF の project.opf、またはドローン写真のフォルダ（カメラは EXIF/XMP タグから：粗い値です。ログの不確かさを参照）</translation>
    </message>
    <message>
      <source>Metashape chunk (label or index) or OpenSfM reconstruction index: needed when the project has several</source>
      <translation>Metashape のチャンク（ラベルまたは番号）または OpenSfM の再構成の番号：プロジェクトに複数あるときに必要</translation>
    </message>
    <message>
      <source>Project CRS (override)</source>
      <translation>プロジェクトの座標参照系（上書き）</translation>
    </message>
    <message>
      <source>Altitude in the tags (GNSS; RTK: ellipsoidal)</source>
      <translation>タグの高度（GNSS。RTK：楕円体高）</translation>
    </message>
    <message>
      <source>Relative altitude + the take-off height below</source>
      <translation>相対高度 + 下の離陸地点の高さ</translation>
    </message>
    <message>
      <source>Relative altitude + the DSM under the first photo</source>
      <translation>相対高度 + 最初の写真の真下の DSM</translation>
    </message>
    <message>
      <source>Camera heights from the DSM under the first photo need a DSM: set 'DSM', or give the take-off height.</source>
      <translation>最初の写真の真下の DSM からカメラの高さを求めるには DSM が必要です。「DSM」を設定するか、離陸地点の高さを指定してください。</translation>
    </message>
    <message>
      <source>Photogrammetry project or folder of photos</source>
      <translation>写真測量プロジェクトまたは写真フォルダ</translation>
    </message>
    <message>
      <source>Chunk or reconstruction</source>
      <translation>チャンクまたは再構成</translation>
    </message>
    <message>
      <source>Camera heights from the relative altitude need the take-off height: set 'Take-off height'.</source>
      <translation>相対高度からカメラの高さを求めるには離陸地点の高さが必要です。「離陸地点の高さ」を設定してください。</translation>
    </message>
    <message>
      <source>Photogrammetry project: none given ({what}).</source>
      <translation>写真測量プロジェクト：指定されていません（{what}）。</translation>
    </message>
    <message>
      <source>{path}: the project's CRS is unknown (a Pix4D project without *_wkt.prj, or an OpenSfM dataset without GPS): set 'Project CRS'.</source>
      <translation>{path}：プロジェクトの CRS が不明です（*_wkt.prj のない Pix4D プロジェクト、または GPS のない OpenSfM データセット）。「プロジェクトの座標参照系」を設定してください。</translation>
    </message>
    <message>
      <source>{n} camera(s) are not aligned and have no pose: {names}</source>
      <translation>{n} 台のカメラは位置合わせされておらず、姿勢がありません：{names}</translation>
    </message>
    <message>
      <source>Name field (default: feature id)</source>
      <translation>名前フィールド（既定：地物 ID）</translation>
    </message>
    <message>
      <source>Heights of the ROI vertices</source>
      <translation>ROI 頂点の高さ</translation>
    </message>
    <message>
      <source>DSM (GeoTIFF): vertex heights and occlusion test</source>
      <translation>DSM（GeoTIFF）：頂点の高さと遮蔽の判定</translation>
    </message>
    <message>
      <source>Height attribute</source>
      <translation>高さの属性</translation>
    </message>
    <message>
      <source>Constant ground height: give the height, or choose another height source.</source>
      <translation>一定の地面の高さ：高さを入力するか、別の高さの取得元を選択してください。</translation>
    </message>
    <message>
      <source>Geometry Z (3-D polygons)</source>
      <translation>ジオメトリの Z（3 次元ポリゴン）</translation>
    </message>
    <message>
      <source>DSM, sampled at every vertex</source>
      <translation>DSM（各頂点でサンプリング）</translation>
    </message>
    <message>
      <source>Attribute (one height per ROI)</source>
      <translation>属性（ROI ごとに 1 つの高さ）</translation>
    </message>
    <message>
      <source>Constant ground height</source>
      <translation>一定の地面の高さ</translation>
    </message>
    <message>
      <source>Constant ground height (project vertical reference)</source>
      <translation>一定の地面の高さ（プロジェクトの高さ基準）</translation>
    </message>
    <message>
      <source>Heights from the DSM: choose the DSM raster, or another height source.</source>
      <translation>DSM から高さを取得：DSM ラスタを選択するか、別の高さの取得元を選択してください。</translation>
    </message>
    <message>
      <source>Heights from an attribute: choose the height attribute of the ROI layer.</source>
      <translation>属性から高さを取得：ROI レイヤの高さの属性を選択してください。</translation>
    </message>
  </context>
</TS>