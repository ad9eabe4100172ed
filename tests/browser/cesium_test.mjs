// SPDX-License-Identifier: Apache-2.0
// A second, independent reader of the tileset (ctest LABEL browser; docs/viewer.md): CesiumJS
// (npm `cesium`) in headless chromium loads OUT/3dtiles/tileset.json from `vdbmap view`,
// refines down to leaves with a close camera, and must report no failed tile and no console
// error. Cesium's files are answered from node_modules by request interception under
// /__cesium/ on the server's origin, so nothing is fetched from the internet (no imagery,
// no terrain, no Ion).
// Usage: node cesium_test.mjs --vdbmap BIN --out OUT [--shots DIR] [--name NAME]
import { readFileSync, existsSync } from 'node:fs';
import { join, normalize } from 'node:path';
import { createRequire } from 'node:module';
import { check, fail, fetchedContents, freshPage, launchChromium, startView, tilesetContents } from './lib.mjs';

const args = Object.fromEntries( process.argv.slice( 2 ).reduce( ( acc, a, i, all ) => {

	if ( a.startsWith( '--' ) ) acc.push( [ a.slice( 2 ), all[ i + 1 ] ] );
	return acc;

}, [] ) );
if ( ! args.out ) fail( 'missing --out' );
const name = args.name || 'run';
const t0 = Date.now();
const cesiumDir = join( createRequire( import.meta.url ).resolve( 'cesium/package.json' ), '..', 'Build', 'Cesium' );
const contents = tilesetContents( args.out );

const PAGE = `<!DOCTYPE html><html><head><meta charset="utf-8"><link rel="icon" href="data:,">
<style>html,body,#c{margin:0;width:100%;height:100%;overflow:hidden}</style>
<script>window.CESIUM_BASE_URL = '/__cesium/';</script><script src="/__cesium/Cesium.js"></script>
<link rel="stylesheet" href="/__cesium/Widgets/widgets.css"></head><body><div id="c"></div><script>
window.result = { loaded: 0, failed: [], allLoaded: false, error: null };
(async () => {
  try {
    const widget = new Cesium.CesiumWidget('c', { baseLayer: false, globe: false, skyBox: false,
      skyAtmosphere: false, shouldAnimate: false, requestRenderMode: false });
    widget.scene.backgroundColor = Cesium.Color.fromBytes(32, 37, 43);
    const tileset = await Cesium.Cesium3DTileset.fromUrl('/out/3dtiles/tileset.json', { maximumScreenSpaceError: 16 });
    widget.scene.primitives.add(tileset);
    tileset.tileLoad.addEventListener(() => { window.result.loaded++; });
    tileset.tileFailed.addEventListener(e => { window.result.failed.push(e.url + ': ' + e.message); });
    tileset.allTilesLoaded.addEventListener(() => { window.result.allLoaded = true; });
    const s = tileset.boundingSphere;
    window.result.radius = s.radius;
    window.closeUp = () => {
      window.result.allLoaded = false;
      widget.camera.lookAt(s.center, new Cesium.HeadingPitchRange(0, -0.9, Math.max(3, s.radius / 12)));
    };
    widget.camera.viewBoundingSphere(s, new Cesium.HeadingPitchRange(0, -0.8, s.radius * 2.2));
  } catch (e) { window.result.error = String(e && e.stack || e); console.error(e); }
})();
</script></body></html>`;

const server = args.url ? { url: args.url, process: { kill() {} } } : await startView( args.vdbmap, args.out );
const browser = await launchChromium();
let ok = false;
try {

	const { page, log, context } = await freshPage( browser, 800, 500 ); // small: SwiftShader's time is per pixel
	await page.setRequestInterception( true );
	page.on( 'request', request => {

		const url = new URL( request.url() );
		if ( url.pathname === '/__cesium/test.html' ) return request.respond( { status: 200, contentType: 'text/html', body: PAGE } );
		if ( url.pathname.startsWith( '/__cesium/' ) ) {

			const file = normalize( join( cesiumDir, decodeURIComponent( url.pathname.slice( 10 ) ) ) );
			if ( file.startsWith( cesiumDir ) && existsSync( file ) ) {

				const type = file.endsWith( '.js' ) ? 'text/javascript' : file.endsWith( '.css' ) ? 'text/css' : file.endsWith( '.json' ) ? 'application/json' : 'application/octet-stream';
				return request.respond( { status: 200, contentType: type, body: readFileSync( file ) } );

			}
			return request.respond( { status: 404, body: 'not found' } );

		}
		if ( url.origin + '/' !== server.url ) return request.abort(); // nothing from the internet
		return request.continue();

	} );
	await page.goto( server.url + '__cesium/test.html', { waitUntil: 'load' } );
	// Waits until Cesium reports all tiles loaded, an error or a failed tile, or the console
	// an error (Cesium stops rendering on a shader error: no need to wait for the timeout).
	const settled = async ( what ) => {

		const start = Date.now();
		for ( ;; ) {

			const r = await page.evaluate( () => window.result || null );
			if ( r && ( r.allLoaded || r.error || r.failed.length ) ) return;
			if ( log.errors.length ) fail( `${ name } CesiumJS ${ what }: ${ log.errors.join( ' | ' ) }` );
			if ( Date.now() - start > 45000 ) fail( `${ name } CesiumJS ${ what }: not loaded after 45 s: ${ JSON.stringify( r ) }` );
			await new Promise( resolve => setTimeout( resolve, 250 ) );

		}

	};
	await settled( 'overview' );
	await page.evaluate( () => window.closeUp && window.closeUp() );
	await settled( 'close-up' );
	const result = await page.evaluate( () => window.result );
	if ( args.shots ) await page.screenshot( { path: join( args.shots, `cesium_${ name }.jpg` ), type: 'jpeg', quality: 85 } );
	check( ! result.error, `${ name } CesiumJS read the tileset${ result.error ? ': ' + result.error : '' }` );
	check( result.failed.length === 0, `${ name } CesiumJS: no failed tile${ result.failed.length ? ': ' + result.failed.join( ' | ' ) : '' }` );
	const fetched = fetchedContents( log.requests, contents );
	const leaves = fetched.filter( p => contents.get( p ).leaf );
	check( result.loaded > 0 && leaves.length > 0, `${ name } CesiumJS loaded ${ result.loaded } tile contents, ${ leaves.length } of them leaves` );
	const errors = log.errors.filter( e => ! /__cesium\/.*404|net::ERR_FAILED.*(ion|cesium\.com)/.test( e ) );
	check( errors.length === 0, `${ name } CesiumJS: no console errors${ errors.length ? ': ' + errors.join( ' | ' ) : '' }` );
	await context.close();
	ok = process.exitCode !== 1;

} finally {

	await browser.close();
	server.process.kill( 'SIGTERM' );
	console.log( `${ name } (CesiumJS): ${ ok ? 'passed' : 'FAILED' } in ${ ( ( Date.now() - t0 ) / 1000 ).toFixed( 1 ) } s` );

}
