// SPDX-License-Identifier: Apache-2.0
// Shared helpers of the browser tests: start `vdbmap view`, start headless chromium with
// software WebGL, read a tileset's content tree, read pixels of the page's WebGL canvas.
import { spawn } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { dirname, join, posix } from 'node:path';
import puppeteer from 'puppeteer-core';

export const CHROMIUM_ARGS = [
	'--headless=new', '--use-gl=angle', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
	'--no-sandbox', '--disable-gpu-sandbox', '--no-first-run', '--no-default-browser-check',
	'--disable-background-networking', '--disable-component-update', '--disable-extensions',
	'--disable-background-timer-throttling', '--disable-renderer-backgrounding',
	'--disable-dev-shm-usage',
];

export function fail( message ) {

	console.error( `FAIL: ${ message }` );
	process.exitCode = 1;
	throw new Error( message );

}

/** Reports a check; a failed one sets the exit code and the run goes on (all checks reported). */
export function check( condition, message ) {

	if ( condition ) console.log( `ok: ${ message }` );
	else {

		console.error( `FAIL: ${ message }` );
		process.exitCode = 1;

	}
	return condition;

}

/** Starts `vdbmap view OUT --port 0 --no-open`; resolves {url, process} once it prints its address. */
export function startView( vdbmap, outDir ) {

	return new Promise( ( resolve, reject ) => {

		const child = spawn( vdbmap, [ 'view', outDir, '--port', '0', '--no-open' ], { stdio: [ 'ignore', 'pipe', 'pipe' ] } );
		let text = '';
		const onData = chunk => {

			text += chunk;
			const m = text.match( /http:\/\/127\.0\.0\.1:\d+\// );
			if ( m ) resolve( { url: m[ 0 ], process: child } );

		};
		child.stdout.on( 'data', onData );
		child.stderr.on( 'data', onData );
		child.on( 'exit', code => reject( new Error( `vdbmap view exited with ${ code }: ${ text }` ) ) );

	} );

}

export async function launchChromium() {

	return puppeteer.launch( {
		executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
		args: CHROMIUM_ARGS,
		headless: true,
		protocolTimeout: 120000,
	} );

}

/**
 * A fresh page in its own browser context (empty cache), logging console errors, page errors,
 * failed requests and every requested URL.
 */
export async function freshPage( browser, width = 1280, height = 800 ) {

	const context = await browser.createBrowserContext();
	const page = await context.newPage();
	await page.setViewport( { width, height } );
	const log = { errors: [], requests: [] };
	page.on( 'console', m => {

		if ( m.type() === 'error' ) log.errors.push( `console: ${ m.text().slice( 0, 400 ) }` );

	} );
	page.on( 'pageerror', e => log.errors.push( `page error: ${ e.message }` ) );
	page.on( 'requestfailed', r => log.errors.push( `request failed: ${ r.url() } ${ r.failure() && r.failure().errorText }` ) );
	page.on( 'response', r => {

		if ( r.status() >= 400 ) log.errors.push( `HTTP ${ r.status() }: ${ r.url() }` );

	} );
	page.on( 'request', r => log.requests.push( r.url() ) );
	return { context, page, log };

}

/**
 * The tileset's contents: Map path-below-OUT -> {depth, leaf}; external tileset.json files
 * are followed. Paths are relative to OUT (as the server serves them at /out/).
 */
export function tilesetContents( outDir ) {

	const contents = new Map();
	const visitFile = ( relFile, depth0 ) => {

		const json = JSON.parse( readFileSync( join( outDir, relFile ), 'utf8' ) );
		const base = posix.dirname( relFile );
		const visit = ( tile, depth ) => {

			const list = [ ...( tile.content ? [ tile.content ] : [] ), ...( tile.contents || [] ) ];
			for ( const c of list ) {

				const rel = posix.normalize( posix.join( base, c.uri || c.url ) );
				if ( rel.endsWith( '.json' ) ) visitFile( rel, depth + 1 );
				else contents.set( rel, { depth, leaf: ! tile.children || tile.children.length === 0 } );

			}
			for ( const child of tile.children || [] ) visit( child, depth + 1 );

		};
		visit( json.root, depth0 );

	};
	visitFile( '3dtiles/tileset.json', 0 );
	return contents;

}

/** Content paths (below OUT) among the requested URLs. */
export function fetchedContents( requests, contents ) {

	const out = [];
	for ( const url of requests ) {

		const m = new URL( url ).pathname.match( /^\/out\/(.*)$/ );
		if ( m && contents.has( decodeURIComponent( m[ 1 ] ) ) ) out.push( decodeURIComponent( m[ 1 ] ) );

	}
	return [ ...new Set( out ) ];

}

/** Statistics of the WebGL canvas: {distinctColours, nonBackground (share of pixels), pixels at points}. */
export async function canvasStats( page, points = [] ) {

	return page.evaluate( ( pts ) => {

		const gl = document.querySelector( '#view canvas' );
		const c = document.createElement( 'canvas' );
		c.width = gl.width;
		c.height = gl.height;
		const ctx = c.getContext( '2d' );
		ctx.drawImage( gl, 0, 0 );
		const { data } = ctx.getImageData( 0, 0, c.width, c.height );
		const bg = [ 32, 37, 43 ]; // the page's background, 0x20252b
		const colours = new Set();
		let different = 0;
		for ( let i = 0; i < data.length; i += 4 * 7 ) {

			colours.add( ( data[ i ] << 16 ) | ( data[ i + 1 ] << 8 ) | data[ i + 2 ] );
			if ( Math.abs( data[ i ] - bg[ 0 ] ) + Math.abs( data[ i + 1 ] - bg[ 1 ] ) + Math.abs( data[ i + 2 ] - bg[ 2 ] ) > 12 ) different ++;

		}
		const scale = c.width / window.innerWidth;
		const pixels = pts.map( ( [ x, y ] ) => {

			const i = 4 * ( Math.round( y * scale ) * c.width + Math.round( x * scale ) );
			return [ data[ i ], data[ i + 1 ], data[ i + 2 ] ];

		} );
		return { distinctColours: colours.size, nonBackground: different / ( data.length / 28 ), background: bg, pixels };

	}, points );

}

/** The drive path's positions [[x, y, z], ...] (W, metres) from drive_path.json. */
export function drivePathPoints( json ) {

	const isPoint = p => Array.isArray( p ) && p.length >= 3 && p.slice( 0, 3 ).every( x => typeof x === 'number' );
	const visit = ( v, depth ) => {

		if ( depth > 4 || ! v || typeof v !== 'object' ) return null;
		if ( Array.isArray( v ) ) {

			if ( v.length && v.every( isPoint ) ) return v;
			if ( v.length && v.every( p => p && typeof p === 'object' && ! Array.isArray( p ) ) ) {

				const pts = v.map( p => Object.values( p ).find( isPoint ) );
				return pts.every( Boolean ) ? pts : null;

			}
			return null;

		}
		for ( const value of Object.values( v ) ) {

			const found = visit( value, depth + 1 );
			if ( found ) return found;

		}
		return null;

	};
	return visit( json, 0 ) || [];

}

/**
 * W's up axis [x, y, z] for a tileset.json object: the W direction its root transform T turns
 * onto the tileset's up (+z; for a geo-referenced T, the direction of T's origin from the
 * Earth's centre); without T: extras.up_axis (0/1/2 or 'x'/'y'/'z'), else z.
 */
export function upAxisW( tileset ) {

	const e = tileset.root && tileset.root.transform;
	if ( e ) {

		const t = [ e[ 12 ], e[ 13 ], e[ 14 ] ];
		const len = Math.hypot( ...t );
		const up = len > 1e5 ? t.map( x => x / len ) : [ 0, 0, 1 ];
		const w = [ 0, 1, 2 ].map( k => e[ 4 * k ] * up[ 0 ] + e[ 4 * k + 1 ] * up[ 1 ] + e[ 4 * k + 2 ] * up[ 2 ] );
		const n = Math.hypot( ...w );
		if ( n > 1e-6 ) return w.map( x => x / n );

	}
	const named = tileset.extras ? tileset.extras.up_axis : undefined;
	const k = typeof named === 'number' ? named : ( { x: 0, y: 1, z: 2 } )[ String( named ).toLowerCase() ];
	const up = [ 0, 0, 0 ];
	up[ k === 0 || k === 1 ? k : 2 ] = 1;
	return up;

}

export const here = dirname( new URL( import.meta.url ).pathname );
